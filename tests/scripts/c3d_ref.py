# SPDX-License-Identifier: MIT
"""An independent C3D reader for the tests of sfit's C3D writer
(tests/scripts/test_cli_c3d.sh, tools/python/tests/test_c3d.py; not a test).

Written from the format description with struct and numpy; shares no code
with tools/formats/c3d.c or c3d_write.c. It returns everything a file holds:
the header words, every group and parameter (type, dimensions, decoded
values, description, locked flag), every point sample (x, y, z, residual as
stored, scaled) and every analog word, so a test can compare two files
field by field.

Where a parameter's link to the next entry leads to no entry (c3d.org's
SGI sample), this reader tries the other byte order, then the entry's own
length. read(path) is strict: the plain format, as the writer must write
it. read(path, strict=False) applies, written separately from sfit's
reader, the repairs docs/c3d.md lists (the section read to the data
section, a walk ended at a link that leads nowhere, no groups, the analog
layout and the frame count decided by the data section's size) and raises
ValueError where a file is refused (tests/scripts/c3d_corpus.py).
"""
import struct

import numpy as np

BLOCK = 512
INTEL, DEC, MIPS = 84, 85, 86


def _order(proc):
    return '>' if proc == MIPS else '<'


def _floats(raw, proc):
    """float32 array from 4-byte words in the processor's format."""
    if proc == DEC:
        a = np.frombuffer(raw, dtype='<u2').reshape(-1, 2)
        # VAX F: halves swapped; value = IEEE value with exponent - 2
        u = (a[:, 0].astype(np.uint32) << 16) | a[:, 1].astype(np.uint32)
        e = (u >> 23) & 0xff
        f = np.zeros(len(u), dtype=np.float64)
        ok = e != 0
        sign = np.where(u >> 31, -1.0, 1.0)
        mant = 1.0 + (u & 0x7fffff).astype(np.float64) / 8388608.0
        f[ok] = sign[ok] * np.ldexp(mant[ok], (e[ok].astype(np.int64) - 129))
        f[(~ok) & ((u >> 31) == 1)] = np.nan
        return f.astype(np.float32)
    return np.frombuffer(raw, dtype=_order(proc) + 'f4').astype(np.float32)


def _ints(raw, proc, unsigned=False):
    return np.frombuffer(raw, dtype=_order(proc) + ('u2' if unsigned else 'i2')).astype(np.int64)


class Param:
    def __init__(self, group, name, typ, dims, raw, desc, locked):
        self.group, self.name, self.type, self.dims = group, name, typ, dims
        self.raw, self.desc, self.locked = raw, desc, locked

    def values(self, proc):
        if self.type == -1:
            return self.raw
        if self.type == 1:
            return np.frombuffer(self.raw, dtype=np.uint8).astype(np.int64)
        if self.type == 2:
            return _ints(self.raw, proc)
        return _floats(self.raw, proc)

    def strings(self):
        """A char array as its list of strings (trailing blanks removed)."""
        if not self.dims:
            return [self.raw.decode('latin-1').rstrip(' \0')]
        w = self.dims[0]
        n = len(self.raw) // w if w else 0
        return [self.raw[i * w:(i + 1) * w].decode('latin-1').rstrip(' \0') for i in range(n)]


def _printable_entry(buf, off, end):
    """Something that can start an entry at `off`: the end mark, or a name
    length byte followed by id, a printable name and its link word."""
    if off + 1 > end:
        return False
    nl = abs(struct.unpack('b', buf[off:off + 1])[0])
    if nl == 0:
        return True
    if off + 4 + nl > end:
        return False
    return all(0x20 <= ch < 0x7f for ch in buf[off + 2:off + 2 + nl])


def _walk(buf, ps, proc, data_start):
    """Every entry of the parameter section, in file order. The section ends
    at its declared size, or at the data section when that is later (the
    declared size of some writers is too small). A link that does not lead to
    an entry is read in the other byte order, else the entry's own length is
    used; when neither gives an entry the walk stops there (returned as
    `stopped`: (entry name, byte of the link word, byte it points to))."""
    e = _order(proc)
    declared = ps + buf[ps + 2] * BLOCK if buf[ps + 2] else ps
    end = max(declared, data_start) if data_start > declared else (declared if buf[ps + 2] else len(buf))
    end = min(end, len(buf))
    out, repaired, stopped, reach = [], [], None, ps + 4
    off = ps + 4
    while off + 2 <= end:
        nl = struct.unpack('b', buf[off:off + 1])[0]
        gid = struct.unpack('b', buf[off + 1:off + 2])[0]
        if nl == 0:
            break
        if off + 4 + abs(nl) > end:
            raise ValueError('parameter section truncated')
        locked = nl < 0
        nl = abs(nl)
        name = buf[off + 2:off + 2 + nl].decode('latin-1').upper()
        lw = off + 2 + nl
        link = struct.unpack(e + 'H', buf[lw:lw + 2])[0]
        q = lw + 2
        if gid < 0:
            dl = buf[q] if q < end else 0
            ent = ('group', -gid, name, buf[q + 1:q + 1 + dl], locked, None)
            size = 1 + dl
        else:
            typ = struct.unpack('b', buf[q:q + 1])[0]
            nd = buf[q + 1]
            dims = list(buf[q + 2:q + 2 + nd])
            cnt = int(np.prod(dims)) if dims else 1
            d0 = q + 2 + nd
            raw = buf[d0:d0 + cnt * abs(typ)]
            dl = buf[d0 + cnt * abs(typ)] if d0 + cnt * abs(typ) < end else 0
            desc = buf[d0 + cnt * abs(typ) + 1:d0 + cnt * abs(typ) + 1 + dl]
            ent = ('param', gid, name, desc, locked, (typ, dims, raw))
            size = 2 + nd + cnt * abs(typ) + 1 + dl
        out.append(ent)
        reach = max(reach, min(q + size, end))
        if link == 0:
            break
        nxt = lw + link
        if link < 2 or nxt > end or not _printable_entry(buf, nxt, end):
            sw = ((link & 0xff) << 8) | (link >> 8)
            if sw >= 2 and lw + sw <= end and _printable_entry(buf, lw + sw, end):
                repaired.append(name)
                nxt = lw + sw
            elif _printable_entry(buf, q + size, end):
                repaired.append(name)
                nxt = q + size
            else:
                stopped = (name, lw, nxt)
                break
        off = nxt
    return out, repaired, stopped, reach, declared


def read(path, strict=True):
    """Read a C3D file. `strict`: the plain format (the writer's tests);
    False: the repairs of the field's readers as docs/c3d.md lists them
    (raises ValueError where the file is refused)."""
    buf = open(path, 'rb').read()
    assert buf[1] == 0x50, 'not a C3D file'
    pblock = buf[0]
    ps = (pblock - 1) * BLOCK
    proc = buf[ps + 3]
    no_section = False
    if proc not in (INTEL, DEC, MIPS):
        # no parameter section: the header's data block is the parameter block
        le, be = struct.unpack('<H', buf[16:18])[0], struct.unpack('>H', buf[16:18])[0]
        if strict or pblock not in (le, be):
            raise ValueError('unknown processor %d' % proc)
        no_section = True
        proc = MIPS if pblock != le else INTEL
        if proc == INTEL:
            r = struct.unpack('<f', buf[20:24])[0]
            if not (np.isfinite(r) and 0 < r < 1e6):
                proc = DEC
    e = _order(proc)
    words = list(struct.unpack(e + '256H', buf[:BLOCK]))
    if not no_section and words[8] == pblock:
        no_section = not strict
    hdr_scale = float(_floats(buf[12:16], proc)[0])
    hdr_rate = float(_floats(buf[20:24], proc)[0])
    notes = []
    ents, repaired, stopped = [], [], None
    if not no_section:
        ents, repaired, stopped, reach, declared = _walk(buf, ps, proc, (words[8] - 1) * BLOCK if strict is False else 0)
        if reach > declared and buf[ps + 2]:
            notes.append('section runs past its declared size')
    groups, params, order = {}, {}, []
    for kind, gid, name, desc, locked, body in ents:
        if kind == 'group':
            groups[gid] = (name, desc, locked)
            order.append(('group', name))
        else:
            params[(gid, name)] = body + (desc, locked)
            order.append(('param', gid, name))
    gname = {g: v[0] for g, v in groups.items()}
    P = {}
    for (gid, name), (typ, dims, raw, desc, locked) in params.items():
        P[(gname.get(gid, '?%d' % gid), name)] = Param(gname.get(gid), name, typ, dims, raw, desc, locked)
    G = {v[0]: (v[1], v[2]) for v in groups.values()}
    if groups and 'POINT' not in G:
        raise ValueError('no POINT group')
    if stopped is not None:
        need = [('POINT', 'USED'), ('POINT', 'SCALE'), ('POINT', 'RATE')]
        if words[1]:
            need.append(('POINT', 'LABELS'))
        if words[2]:
            need += [('ANALOG', 'USED'), ('ANALOG', 'RATE')]
        missing = [k for k in need if k not in P]
        if strict or missing:
            raise ValueError('the link after %s leads nowhere%s' % (stopped[0], ', %s:%s not read' % missing[0] if missing else ''))
        notes.append('walk ended at %s' % stopped[0])

    def num(g, n, default=None):
        p = P.get((g, n))
        if p is None:
            return default
        v = p.values(proc)
        return v[0].item() if hasattr(v[0], 'item') else v[0]

    npts = words[1]
    used = num('POINT', 'USED')
    if used is not None and used % 65536 != npts:
        raise ValueError('POINT:USED %d, header %d' % (used, npts))
    scale = num('POINT', 'SCALE', hdr_scale)
    rate = num('POINT', 'RATE', hdr_rate)
    dblock = num('POINT', 'DATA_START', words[8])
    if dblock is not None and dblock < 0:
        dblock += 65536
    if not dblock:  # a POINT:DATA_START of 0: the header's
        dblock = words[8]
    nanalog = words[2]
    first, last = words[3], words[4]
    hframes = last - first + 1 if last >= first else 0
    pframes = num('POINT', 'FRAMES')
    if pframes is not None and pframes < 0:
        pframes += 65536
    if pframes is not None:
        pframes = int(pframes) if pframes == int(pframes) else None
    word = 4 if scale < 0 else 2
    d0 = (dblock - 1) * BLOCK
    nbytes = len(buf) - d0
    if strict:
        nframes = pframes if pframes is not None else hframes
    else:
        # analog words per frame: header, or ANALOG:USED x the rate ratio
        au, ar = num('ANALOG', 'USED'), num('ANALOG', 'RATE')
        if au is not None and ar and rate and ar > 0 and rate > 0:
            ratio = ar / rate
            if round(ratio) >= 1 and abs(ratio - round(ratio)) <= 1e-3 * round(ratio) and au * round(ratio) != nanalog:
                def ends(fb):
                    return [n for n in (hframes, pframes) if n and n * fb <= nbytes and nbytes - n * fb < BLOCK]
                alt = int(au * round(ratio))
                h_ok = bool(ends((4 * npts + nanalog) * word))
                p_ok = bool(ends((4 * npts + alt) * word))
                if h_ok == p_ok:
                    raise ValueError('analog layout conflict: header %d, parameters %d' % (nanalog, alt))
                if p_ok:
                    nanalog = alt
                notes.append('analog layout by the data size')
        fb = (4 * npts + nanalog) * word
        held = nbytes // fb if fb else 0
        complete = held >= 1 and (nbytes - held * fb == 0 or len(buf) % BLOCK == 0)

        def zero(a, b):
            return not any(buf[d0 + a * fb:d0 + b * fb])

        def trimmed_held():
            n = held
            while n > 1 and d0 + (n - 1) * fb + BLOCK >= len(buf) and zero(n - 1, n):
                n -= 1
            return n
        if pframes is None or pframes == hframes:
            nframes = hframes
            if nframes > held:
                if not complete:
                    raise ValueError('truncated')
                nframes = trimmed_held()
        else:
            if hframes > held and pframes > held:
                if not complete:
                    raise ValueError('truncated')
                nframes = trimmed_held()
            elif hframes <= held and pframes <= held:
                lo, hi = min(hframes, pframes), max(hframes, pframes)
                nframes = lo if zero(lo, hi) else hi
            else:
                nframes = hframes if hframes <= held else pframes
        # long counts (above 65535)
        lf = P.get(('POINT', 'LONG_FRAMES'))
        if lf is not None:
            v = lf.values(proc)
            n = int(v[0]) % 65536 + 65536 * (int(v[1]) % 65536) if lf.type == 2 and len(v) >= 2 else int(v[0])
            if n > 65535:
                nframes = min(n, held) if complete or n <= held else None
                if nframes is None:
                    raise ValueError('truncated')
    fb = (4 * npts + nanalog) * word
    data = buf[d0:d0 + nframes * fb]
    assert len(data) == nframes * fb, "data section short: %d frames of %d bytes from byte %d, %d bytes" % (nframes, fb, d0, len(buf))
    fmt = P.get(('ANALOG', 'FORMAT'))
    unsigned = fmt is not None and len(fmt.strings()) > 0 and fmt.strings()[0].upper().startswith('UNSIGNED')
    if word == 4:
        allw = _floats(data, proc).reshape(nframes, -1)
        pts = allw[:, :4 * npts].reshape(nframes, npts, 4).astype(np.float64)
        analog = allw[:, 4 * npts:].astype(np.float64)
        xyz = pts[:, :, :3]
        res = pts[:, :, 3]
        raw_pts = pts
    else:
        alli = _ints(data, proc).reshape(nframes, -1)
        raw_pts = alli[:, :4 * npts].reshape(nframes, npts, 4)
        xyz = (raw_pts[:, :, :3].astype(np.float32) * np.float32(scale)).astype(np.float64)
        res = raw_pts[:, :, 3].astype(np.float64)
        analog = (_ints(data, proc, unsigned).reshape(nframes, -1)[:, 4 * npts:]).astype(np.float64)
    labels = []
    for k in range(1, 100):
        p = P.get(('POINT', 'LABELS' if k == 1 else 'LABELS%d' % k))
        if p is None:
            break
        labels += p.strings()
    descs = []
    for k in range(1, 100):
        p = P.get(('POINT', 'DESCRIPTIONS' if k == 1 else 'DESCRIPTIONS%d' % k))
        if p is None:
            break
        descs += p.strings()
    return dict(proc=proc, words=words, header_scale=hdr_scale, header_rate=hdr_rate,
                groups=G, params=P, order=order, npoints=npts, nframes=nframes, scale=scale,
                rate=rate, data_block=dblock, word=word, xyz=xyz, residual=res, raw_points=raw_pts,
                analog=analog, labels=labels[:npts], all_labels=labels, descriptions=descs,
                units=(P[('POINT', 'UNITS')].strings()[0] if ('POINT', 'UNITS') in P else ''),
                notes=notes, repaired=repaired)


def read_trc(path):
    """An OpenSim TRC file by its header rules: line 1 PathFileType,
    line 2 the names of line 3's values (DataRate ... OrigNumFrames),
    line 4 Frame#, Time and the marker names (each followed by two blank
    cells), line 5 X1 Y1 Z1 ..., then (after an optional blank line) one row
    per frame, tab-separated; a blank cell is a missing coordinate."""
    lines = open(path).read().split('\n')
    assert lines[0].split('\t')[0] == 'PathFileType', lines[0]
    keys = lines[1].split('\t')
    vals = lines[2].split('\t')
    assert len(keys) == len(vals), (keys, vals)
    meta = dict(zip(keys, vals))
    h4 = lines[3].split('\t')
    assert h4[0] == 'Frame#' and h4[1] == 'Time', h4
    names = [h4[i] for i in range(2, len(h4), 3) if h4[i] != '']
    h5 = lines[4].split('\t')
    want = ['', ''] + [c for k in range(len(names)) for c in ('X%d' % (k + 1), 'Y%d' % (k + 1), 'Z%d' % (k + 1))]
    assert h5 == want, (h5[:8], want[:8])
    rows = [l for l in lines[5:] if l.strip() != '']
    frames, times, xyz = [], [], []
    for r in rows:
        c = r.split('\t')
        assert len(c) == 2 + 3 * len(names), (len(c), len(names))
        frames.append(int(c[0]))
        times.append(float(c[1]))
        xyz.append([float(v) if v != '' else np.nan for v in c[2:]])
    return dict(meta=meta, names=names, frames=frames, times=np.array(times),
                xyz=np.array(xyz).reshape(len(rows), len(names), 3))


def check_added(orig, new, names, xyz, prefix=''):
    """The file `new` is `orig` (both from read()) with points `names`
    added (xyz: frames x n x 3, NaN = not placed): raise AssertionError
    on any other difference. Returns the largest error of a new point."""
    n = len(names)
    np_ = orig['npoints']
    assert new['proc'] == orig['proc']
    assert new['npoints'] == np_ + n and new['nframes'] == orig['nframes']
    to_float = orig['word'] == 2 and new['word'] == 4
    # header: every word but the point count, the scale (when converted) and the data block;
    # the analog words per frame and the last frame say the layout and frames written
    for i, (a, b) in enumerate(zip(orig['words'], new['words'])):
        if i in (1, 8) or (to_float and i in (6, 7)):
            continue
        if i == 2 and b == orig['analog'].shape[1]:
            continue
        if i == 4 and b == orig['words'][3] + orig['nframes'] - 1:
            continue
        assert a == b, 'header word %d: %d -> %d' % (i + 1, a, b)
    assert new['words'][1] == np_ + n
    # parameters: every one identical, but the ones adding points changes
    changed = {('POINT', 'USED'), ('POINT', 'DATA_START')}
    if ('POINT', 'FRAMES') in new['params']:
        assert new['params'][('POINT', 'FRAMES')].values(new['proc'])[0] % 65536 == orig['nframes'] % 65536
        changed.add(('POINT', 'FRAMES'))
    if to_float:
        changed.add(('POINT', 'SCALE'))
    fam = lambda k: k[0] == 'POINT' and (k[1].startswith('LABELS') or k[1].startswith('DESCRIPTIONS'))
    assert set(orig['groups']) == set(new['groups'])
    for g, (desc, locked) in orig['groups'].items():
        assert new['groups'][g] == (desc, locked), g
    for key, p in orig['params'].items():
        assert key in new['params'], key
        q = new['params'][key]
        if key in changed or fam(key):
            continue
        assert (q.type, q.dims, q.raw, q.desc, q.locked) == (p.type, p.dims, p.raw, p.desc, p.locked), key
    extra = set(new['params']) - set(orig['params'])
    assert all(fam(k) for k in extra), extra
    assert new['params'][('POINT', 'USED')].values(new['proc'])[0] % 65536 == np_ + n
    if ('POINT', 'DATA_START') in orig['params']:
        assert new['params'][('POINT', 'DATA_START')].values(new['proc'])[0] % 65536 == new['data_block']
    if to_float:
        assert new['scale'] == -abs(orig['scale'])
    full = [prefix + s for s in names]
    assert new['all_labels'][:np_] == orig['all_labels'][:np_]
    assert new['all_labels'][np_:np_ + n] == full, new['all_labels'][np_:np_ + n]
    assert new['all_labels'][np_ + n:] == orig['all_labels'][np_:], 'labels past the points'
    for k in list(new['params']):
        if k[0] == 'POINT' and k[1].startswith('LABELS'):
            assert new['params'][k].dims[1] <= 255
    od, nd = orig['descriptions'], new['descriptions']
    if od:
        # a DESCRIPTIONS shorter than POINT:USED is padded with blanks up to it
        m = min(len(od), np_)
        assert nd[:m] == od[:m] and all(s == '' for s in nd[m:np_ + n]), nd[:np_ + n]
        assert nd[np_ + n:] == od[np_:], 'descriptions past the points'
        assert len(nd) == max(len(od), np_) + n
    # samples: every original point sample and analog value identical
    if to_float:
        assert np.array_equal(new['xyz'][:, :np_], orig['xyz'][:, :np_], equal_nan=True)
        assert np.array_equal(new['residual'][:, :np_], orig['residual'][:, :np_])
    else:  # a recording may store NaN words for its invalid samples: kept as NaN
        assert np.array_equal(new['raw_points'][:, :np_], orig['raw_points'][:, :np_],
                              equal_nan=True)
    assert np.array_equal(new['analog'], orig['analog'], equal_nan=True), 'analog'
    # the new points where they were put; residual -1 where not placed
    got = new['xyz'][:, np_:]
    res = new['residual'][:, np_:]
    miss = np.isnan(xyz).any(axis=2)
    assert np.all(res[miss] == -1) and np.all(res[~miss] >= 0)
    tol = 0.0 if new['word'] == 4 else abs(new['scale']) / 2 * 1.0001
    err = np.abs(got[~miss] - np.asarray(xyz, dtype=np.float32).astype(np.float64)[~miss])
    worst = float(err.max()) if err.size else 0.0
    assert worst <= tol, (worst, tol)
    return worst
