# SPDX-License-Identifier: MIT
# Shared by the tests/scripts/test_*.sh scripts (sourced, not a test).
# missing MSG: a required tool is absent. In CI (CI=true) that is a
# failure; elsewhere the test is skipped (exit 77, ctest SKIP_RETURN_CODE).
# Uses the caller's $name for the message prefix.
missing() {
  if [ "${CI:-}" = "true" ]; then
    echo "${name:-test}: FAIL: $* (required in CI)" >&2
    exit 1
  fi
  echo "${name:-test}: SKIP: $*"
  exit 77
}

# rule_setup CHECK: the preamble of the scripts that check a rule of the
# tree (test_api_names.sh, test_modules.sh): CHECK (a python script) must
# pass on $src; then a temporary $tmp (removed on exit) and must_fail WHAT,
# which requires CHECK to fail on the broken copy $tmp/t (WHAT: the breach).
rule_setup() {
  [ -x /usr/bin/python3 ] || missing "/usr/bin/python3 not found"
  rule_check=$1
  /usr/bin/python3 "$rule_check" "$src"
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  must_fail() {
    local out
    if out=$(/usr/bin/python3 "$rule_check" "$tmp/t" 2>&1); then
      echo "FAIL: the check passed on a tree with $1" >&2; exit 1
    fi
    echo "ok: fails on $1: $(echo "$out" | head -1)"
  }
}

# cli_setup NAME BUILD_DIR SOURCE_DIR: the preamble of the CLI scripts
# (bash): sets $name, $sfit, $data and a temporary directory $tmp removed on
# exit, requires /usr/bin/python3, and defines fail MSG, py CODE ARGS
# (python3 with tests/scripts on the path) and expect_rc CODE CMD... (runs
# CMD, checks its exit status, keeps its stdout in $out and status in $rc).
cli_setup() {
  name=$1
  sfit="$2/bin/sfit"
  data="$3/tests/data"
  cli_src=$3
  tmp=$(mktemp -d)
  trap 'rm -rf "$tmp"' EXIT
  [ -x /usr/bin/python3 ] || missing "/usr/bin/python3 not found"
  fail() { echo "FAIL: $*" >&2; exit 1; }
  py() { PYTHONPATH="$cli_src/tests/scripts" /usr/bin/python3 -c "$@"; }
  expect_rc() {
    local want=$1; shift
    set +e
    out=$("$@" 2>"$tmp/stderr"); rc=$?
    set -e
    [ "$rc" -eq "$want" ] || fail "'$*': exit $rc, expected $want; stdout: $out; stderr: $(cat "$tmp/stderr")"
  }
}

# Option checks of the CLI scripts (need $sfit, $tmp and fail).
# expect_usage MSG CMD ARGS...: `sfit CMD ARGS...` exits 2 with nothing on
# stdout, the line "sfit: MSG" on stderr, then the usage of CMD.
expect_usage() {
  local want=$1 cmd=$2 rc; shift
  set +e
  "$sfit" "$@" >"$tmp/usage.out" 2>"$tmp/usage.err"; rc=$?
  set -e
  [ "$rc" -eq 2 ] || fail "'sfit $*': exit $rc, expected 2; stderr: $(cat "$tmp/usage.err")"
  [ ! -s "$tmp/usage.out" ] || fail "'sfit $*': stdout not empty: $(cat "$tmp/usage.out")"
  [ "$(sed -n 1p "$tmp/usage.err")" = "sfit: $want" ] \
    || fail "'sfit $*': stderr '$(sed -n 1p "$tmp/usage.err")', expected 'sfit: $want'"
  case $(sed -n 2p "$tmp/usage.err") in
    "usage: sfit $cmd "*) ;;
    *) fail "'sfit $*': no usage of $cmd after the message: $(cat "$tmp/usage.err")" ;;
  esac
}
# expect_help CMD ARGS...: `sfit CMD ARGS...` exits 0 with the usage of CMD
# on stdout and nothing on stderr.
expect_help() {
  local rc
  set +e
  "$sfit" "$@" >"$tmp/usage.out" 2>"$tmp/usage.err"; rc=$?
  set -e
  [ "$rc" -eq 0 ] || fail "'sfit $*': exit $rc, expected 0"
  [ ! -s "$tmp/usage.err" ] || fail "'sfit $*': stderr not empty: $(cat "$tmp/usage.err")"
  case $(sed -n 1p "$tmp/usage.out") in
    "usage: sfit $1 "*) ;;
    *) fail "'sfit $*': stdout is not the usage of $1: $(sed -n 1p "$tmp/usage.out")" ;;
  esac
}

# san_build OUT [TARGET...]: builds TARGETs (default: everything) of $src
# in OUT with gcc's (or $SFIT_SAN_CC's) AddressSanitizer +
# UndefinedBehaviorSanitizer, -fno-sanitize-recover=all (without it UBSan
# only prints and exits 0), Debug -O1 -Werror, and exports ASAN_OPTIONS /
# UBSAN_OPTIONS (unless set) that abort on the first report. Skips
# (missing) when the compiler cannot link a sanitized program. Sets $cc and
# $san; uses the caller's $name and $src.
san_build() {
  local out=$1 req=OFF t; shift
  cc=${SFIT_SAN_CC:-gcc}
  command -v "$cc" >/dev/null 2>&1 || missing "$cc not found"
  command -v cmake >/dev/null 2>&1 || missing "cmake not found"
  san="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
  mkdir -p "$out"
  printf 'int main(void) { return 0; }\n' > "$out/probe.c"
  # shellcheck disable=SC2086
  "$cc" $san "$out/probe.c" -o "$out/probe" >/dev/null 2>&1 || missing "$cc cannot link $san"
  export ASAN_OPTIONS=${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}
  export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
  for t in "$@"; do
    case $t in test_*) req=ON ;; esac # a unit test needs cmocka
  done
  CC="$cc" cmake -S "$src" -B "$out" -DCMAKE_BUILD_TYPE=Debug -DSFIT_WERROR=ON \
    -DSFIT_TESTS_REQUIRE_CMOCKA=$req \
    -DCMAKE_C_FLAGS="$san -O1" -DCMAKE_EXE_LINKER_FLAGS="$san" >"$out/configure.log" 2>&1 \
    || { cat "$out/configure.log" >&2; echo "$name: FAIL: configure" >&2; exit 1; }
  # shellcheck disable=SC2046
  cmake --build "$out" -j2 $([ $# -gt 0 ] && printf -- '--target %s ' "$@") >"$out/build.log" 2>&1 \
    || { tail -n 60 "$out/build.log" >&2; echo "$name: FAIL: build" >&2; exit 1; }
}
