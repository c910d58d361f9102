# SPDX-License-Identifier: MIT
# cmake -DIN=file.js -DOUT=file.h -DNAME=var -P embed_js.cmake: the script
# as a NULL-terminated array of C strings, one per line (no literal over
# C99's 4095 characters, no trigraph).
file(READ "${IN}" js)
string(REPLACE "\\" "\\\\" js "${js}")
string(REPLACE "\"" "\\\"" js "${js}")
string(REPLACE "?" "\\?" js "${js}")
string(REPLACE "\n" "\\n\",\n\"" js "${js}")
file(WRITE "${OUT}" "/* Generated from ${IN} by embed_js.cmake: do not edit. */\n"
     "static const char *const ${NAME}[] = {\n\"${js}\", NULL};\n")
