#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Write the C3D failure-class cases of tests/data/c3d/cases/ (docs/c3d.md).

Each case is a c3d.org sample (tests/data/c3d/c3d_org/s02_*.c3d, the same
recording in Intel and SGI integer storage) cut to 5 frames, with one
defect written in by editing bytes. The files are committed; rerun only to
regenerate them:

    python3 tests/data/c3d/cases/make_cases.py

Written from the format description with `struct`; shares no code with
tools/formats (the reader under test).
"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
SRC = os.path.join(HERE, "..", "c3d_org")
NFRAMES = 5


def entries(b, e):
    """(group_or_param, gid, name, link_offset, body_offset) of every entry;
    the link is followed, or the entry's own length where it leads outside
    the section (the SGI sample's one bad link)."""
    p = (b[0] - 1) * 512
    end = p + b[p + 2] * 512
    off = p + 4
    out = []
    while off + 2 <= end:
        nl = struct.unpack("b", b[off:off + 1])[0]
        gid = struct.unpack("b", b[off + 1:off + 2])[0]
        if nl == 0:
            break
        nl = abs(nl)
        name = b[off + 2:off + 2 + nl].decode("ascii")
        lo = off + 2 + nl
        link = struct.unpack(e + "H", b[lo:lo + 2])[0]
        body = lo + 2
        out.append((gid, name, lo, body))
        if gid > 0:
            typ = struct.unpack("b", b[body:body + 1])[0]
            nd = b[body + 1]
            cnt = 1
            for d in b[body + 2:body + 2 + nd]:
                cnt *= d
            nat = 2 + nd + cnt * abs(typ)
        else:
            nat = 0
        nat += 1 + b[body + nat]
        if link == 0:
            break
        if lo + link > end:
            link = nat + 2
        off = lo + link
    return out


def param(b, e, group, name):
    ents = entries(b, e)
    gid = [-g for g, n, _, _ in ents if g < 0 and n.upper() == group][0]
    for g, n, lo, body in ents:
        if g == gid and n.upper() == name:
            nd = b[body + 1]
            return body + 2 + nd  # data offset
    raise KeyError(group + ":" + name)


def cut(path, nframes=NFRAMES):
    b = bytearray(open(path, "rb").read())
    p = (b[0] - 1) * 512
    e = ">" if b[p + 3] == 86 else "<"
    npts, nan, first = struct.unpack(e + "3H", b[2:8])
    word = 4 if b"real" in os.path.basename(path).encode() else 2
    dblock = struct.unpack(e + "H", b[16:18])[0]
    fb = (4 * npts + nan) * word
    b[8:10] = struct.pack(e + "H", first + nframes - 1)
    q = param(b, e, "POINT", "FRAMES")
    b[q:q + 2] = struct.pack(e + "H", nframes)
    out = b[:(dblock - 1) * 512 + nframes * fb]
    out += b"\0" * (-len(out) % 512)
    return out, e, fb, dblock


def main():
    cases = {}
    pc, e, fb, dblock = cut(os.path.join(SRC, "s02_pc_int.c3d"))
    sgi, _, _, _ = cut(os.path.join(SRC, "s02_sgi_int.c3d"))
    cases["pc_int_5"] = pc
    # SGI: POINT:LABELS links to its successor in the other byte order (as in c3d.org's sample).
    cases["sgi_bad_link"] = sgi
    # The header says 16 analog words per frame; ANALOG:USED 16 x 200/50 Hz and the data say 64.
    x = bytearray(pc)
    x[4:6] = struct.pack(e + "H", 16)
    cases["analog_conflict"] = x
    # The header's last frame says 1149 frames, POINT:FRAMES and the file's size 5.
    x = bytearray(pc)
    x[8:10] = struct.pack(e + "H", 1149)
    cases["frames_header_1149"] = x
    # POINT:FRAMES says 1149, the header and the file's size 5.
    x = bytearray(pc)
    q = param(x, e, "POINT", "FRAMES")
    x[q:q + 2] = struct.pack(e + "H", 1149)
    cases["frames_param_1149"] = x
    # No parameter section: the header's data block (2) is the parameter block.
    x = bytearray(pc[:512]) + pc[(dblock - 1) * 512:]
    x[16:18] = struct.pack(e + "H", 2)
    cases["no_params"] = x
    # The header's scale differs from POINT:SCALE.
    x = bytearray(pc)
    x[12:16] = struct.pack(e + "f", 0.5)
    cases["scale_mismatch"] = x
    # Marker 3 (RFT3) at exactly (0, 0, 0) with residual 0 in frames 2 and 4.
    x = bytearray(pc)
    for f in (1, 3):
        o = (dblock - 1) * 512 + f * fb + 2 * 4 * 2
        x[o:o + 8] = struct.pack(e + "4h", 0, 0, 0, 0)
    cases["zero_marker"] = x
    # Duplicate labels: points 2 and 3 (RFT2, RFT3) both labelled RFT1.
    x = bytearray(pc)
    q = param(x, e, "POINT", "LABELS")
    x[q + 4:q + 8] = b"RFT1"
    x[q + 8:q + 12] = b"RFT1"
    cases["dup_labels"] = x
    # The analog conflict with two more blocks of data: neither layout ends
    # the 5 frames announced in the data section's last block.
    cases["analog_ambiguous"] = bytearray(cases["analog_conflict"]) + bytes(1024)
    # A link that leads nowhere after the parameters that fix the layout
    # (ANALOG:LABELS's link out of the section in both byte orders, the next
    # entry's name unreadable): the walk ends there.
    def break_link(x, after, nxt):
        ents = {n if g < 0 else "%d:%s" % (g, n): (lo, body) for g, n, lo, body in entries(x, e)}
        lo = ents[after][0]
        x[lo:lo + 2] = struct.pack(e + "H", 0xF0F0)
        nlo = ents[nxt][0]
        nl = len(nxt.split(":")[1])
        x[nlo - nl:nlo] = bytes([1]) * nl
        return x
    cases["link_end"] = break_link(bytearray(pc), "2:LABELS", "1:DATA_START")
    # The same before POINT:LABELS was read (after ANALOG:RATE): refused.
    cases["link_early"] = break_link(bytearray(pc), "2:RATE", "1:LABELS")
    # A parameter section without any entry (its first byte the end mark).
    x = bytearray(pc)
    p = (x[0] - 1) * 512
    x[p + 4:p + 6] = bytes(2)
    cases["no_groups"] = x
    # The header and POINT:FRAMES both say 1149; the file holds 5 frames and
    # ends with its last block (a count never updated).
    x = bytearray(pc)
    x[8:10] = struct.pack(e + "H", 1149)
    q = param(x, e, "POINT", "FRAMES")
    x[q:q + 2] = struct.pack(e + "H", 1149)
    cases["frames_both_1149"] = x
    # The header says frames 1..6, POINT:FRAMES 5: the 6th frame's bytes are
    # the last block's zero padding.
    x = bytearray(pc)
    x[8:10] = struct.pack(e + "H", 6)
    cases["frames_pad_6"] = x
    # The first parameter block declares 5 blocks; the entries run on to
    # byte 5748, before the data section (block 13).
    x = bytearray(pc)
    x[(x[0] - 1) * 512 + 2] = 5
    cases["params_past_size"] = x
    for name, data in cases.items():
        with open(os.path.join(HERE, name + ".c3d"), "wb") as fh:
            fh.write(bytes(data))
        print("%s.c3d: %d bytes" % (name, len(data)))


if __name__ == "__main__":
    main()
