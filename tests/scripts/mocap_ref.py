# SPDX-License-Identifier: MIT
"""Independent references for the CLI tests of the C3D reader and `sfit joint`
(imported by tests/scripts/test_cli_input.sh and test_cli_joint.sh; not a test).

- read_c3d / write_c3d: a C3D reader and writer written from the format
  description with `struct`, independently of tools/formats/c3d.c (Intel, DEC
  and MIPS processor types; float or scaled 16-bit integer points).
- kabsch / template / register_all / mgdk: double-precision rigid
  registration (SVD Kabsch with the reflection correction) and the
  multi-marker MGDK common centre, in numpy.
"""
import struct

BLOCK = 512
INTEL, DEC, MIPS = 84, 85, 86


# ------------------------------------------------------------------ C3D
def _endian(proc):
    return '>' if proc == MIPS else '<'


def _f32(buf, off, proc):
    """One 4-byte float. DEC: the two 16-bit halves are swapped relative to
    IEEE little-endian and the exponent bias is 2 higher (divide by 4)."""
    if proc == DEC:
        b = buf[off:off + 4]
        sw = bytes((b[2], b[3], b[0], b[1]))
        if b[1] & 0x7f == 0 and b[0] & 0x80 == 0:  # exponent 0: zero
            return 0.0
        return struct.unpack('<f', sw)[0] / 4.0
    return struct.unpack(_endian(proc) + 'f', buf[off:off + 4])[0]


def _pack_f32(v, proc):
    if proc == DEC:
        if v == 0.0:
            return b'\0\0\0\0'
        b = struct.pack('<f', v * 4.0)
        return bytes((b[2], b[3], b[0], b[1]))
    return struct.pack(_endian(proc) + 'f', v)


def read_c3d(path):
    """Returns dict: proc, labels, rate, units, scale, first, frames (list of
    frames, each a list of (x, y, z) or None for an invalid sample)."""
    buf = open(path, 'rb').read()
    pblock = buf[0]
    assert buf[1] == 0x50, 'not a C3D file'
    pstart = (pblock - 1) * BLOCK
    proc = buf[pstart + 3]
    e = _endian(proc)
    npts, nanalog, first, last = struct.unpack(e + '4H', buf[2:10])
    dblock = struct.unpack(e + 'H', buf[16:18])[0]
    scale = _f32(buf, 12, proc)
    rate = _f32(buf, 20, proc)
    # parameters: walk the entries, groups by id
    groups, params = {}, {}
    off = pstart + 4
    while True:
        nlen = struct.unpack('b', buf[off:off + 1])[0]
        gid = struct.unpack('b', buf[off + 1:off + 2])[0]
        if nlen == 0:
            break
        nlen = abs(nlen)
        name = buf[off + 2:off + 2 + nlen].decode('ascii').upper()
        nxt = struct.unpack(e + 'h', buf[off + 2 + nlen:off + 4 + nlen])[0]
        if gid < 0:
            groups[-gid] = name
        else:
            q = off + 4 + nlen
            typ = struct.unpack('b', buf[q:q + 1])[0]
            nd = buf[q + 1]
            dims = list(buf[q + 2:q + 2 + nd])
            params[(gid, name)] = (typ, dims, q + 2 + nd)
        if nxt == 0:
            break
        off = off + 2 + nlen + nxt
    point = [g for g, n in groups.items() if n == 'POINT'][0]

    def par(name):
        return params.get((point, name))

    def number(p):
        typ, dims, q = p
        if typ == 2:
            return struct.unpack(e + 'h', buf[q:q + 2])[0]
        if typ == 4:
            return _f32(buf, q, proc)
        return buf[q]

    if par('SCALE'):
        scale = number(par('SCALE'))
    if par('RATE'):
        rate = number(par('RATE'))
    if par('DATA_START'):
        dblock = number(par('DATA_START')) & 0xffff
    units = ''
    if par('UNITS'):
        typ, dims, q = par('UNITS')
        units = buf[q:q + dims[0]].decode('ascii').strip()
    labels = []
    for name in ['LABELS'] + ['LABELS%d' % k for k in range(2, 100)]:
        p = par(name)
        if p is None:
            break
        typ, dims, q = p
        ln, cnt = dims[0], (dims[1] if len(dims) > 1 else 1)
        for i in range(cnt):
            labels.append(buf[q + i * ln:q + (i + 1) * ln].decode('ascii').strip())
    labels = labels[:npts]
    nframes = last - first + 1
    word = 4 if scale < 0 else 2
    fsize = (4 * npts + nanalog) * word
    dstart = (dblock - 1) * BLOCK
    frames = []
    for f in range(nframes):
        row = []
        for p in range(npts):
            o = dstart + f * fsize + p * 4 * word
            if word == 4:
                x, y, z, res = (_f32(buf, o + 4 * i, proc) for i in range(4))
            else:
                x, y, z, res = struct.unpack(e + '4h', buf[o:o + 8])
                x, y, z = x * scale, y * scale, z * scale
            row.append(None if res < 0 else (x, y, z))
        frames.append(row)
    return dict(proc=proc, labels=labels, rate=rate, units=units, scale=scale,
                first=first, frames=frames)


def write_c3d(path, labels, frames, proc=INTEL, scale=-1.0, rate=100.0, units='mm',
              first=1, nanalog=0, label_chunk=255):
    """frames: list of frames, each a list of (x, y, z) or None (invalid).
    scale < 0: float storage; > 0: int16 = round(v / scale). Analog words
    (nanalog per frame) are written as zeros. Labels are split into LABELS,
    LABELS2, ... of label_chunk entries."""
    e = _endian(proc)
    npts = len(labels)
    word = 4 if scale < 0 else 2

    def i16(v):
        return struct.pack(e + 'h', v)

    def entry(name, gid, body):
        nb = name.encode('ascii')
        # offset to the next entry counted from the offset word itself
        return struct.pack('bb', len(nb), gid) + nb + i16(2 + len(body)) + body

    def param(name, typ, dims, data):
        return entry(name, 1, struct.pack('bB', typ, len(dims)) + bytes(dims) + data + b'\0')

    chunks = [labels[i:i + label_chunk] for i in range(0, max(npts, 1), label_chunk)]
    body = entry('POINT', -1, b'\0')
    body += param('USED', 2, [], i16(npts))
    body += param('SCALE', 4, [], _pack_f32(scale, proc))
    body += param('RATE', 4, [], _pack_f32(rate, proc))
    body += param('UNITS', -1, [len(units)], units.encode('ascii'))
    for k, ch in enumerate(chunks):
        name = 'LABELS' if k == 0 else 'LABELS%d' % (k + 1)
        data = b''.join(l.ljust(8)[:8].encode('ascii') for l in ch)
        body += param(name, -1, [8, len(ch)], data)
    body += b'\0\0'  # end
    nblocks = (4 + len(body) + BLOCK - 1) // BLOCK
    psec = bytes((1, 0x50, nblocks, proc)) + body
    psec += b'\0' * (nblocks * BLOCK - len(psec))
    dblock = 2 + nblocks
    hdr = bytearray(BLOCK)
    hdr[0], hdr[1] = 2, 0x50
    hdr[2:10] = struct.pack(e + '4H', npts, nanalog, first, first + len(frames) - 1)
    hdr[10:12] = struct.pack(e + 'H', 0)
    hdr[12:16] = _pack_f32(scale, proc)
    hdr[16:18] = struct.pack(e + 'H', dblock)
    hdr[18:20] = struct.pack(e + 'H', 1)
    hdr[20:24] = _pack_f32(rate, proc)
    data = bytearray()
    for row in frames:
        for p in row:
            if word == 4:
                if p is None:
                    data += b''.join(_pack_f32(0.0, proc) for _ in range(3)) + _pack_f32(-1.0, proc)
                else:
                    data += b''.join(_pack_f32(v, proc) for v in p) + _pack_f32(0.0, proc)
            else:
                if p is None:
                    data += struct.pack(e + '4h', 0, 0, 0, -1)
                else:
                    data += struct.pack(e + '4h', *(int(round(v / scale)) for v in p), 0)
        data += b'\0' * (nanalog * word)
    with open(path, 'wb') as f:
        f.write(bytes(hdr) + psec + bytes(data))


# ------------------------------------------------------------ registration
def kabsch(tpl, meas):
    """R, t minimising sum |R p + t - x|^2 over rows without NaN (proper rotation)."""
    import numpy as np
    ok = ~np.isnan(meas).any(axis=1)
    p, x = tpl[ok], meas[ok]
    cp, cx = p.mean(0), x.mean(0)
    h = (x - cx).T @ (p - cp)
    u, _, vt = np.linalg.svd(h)
    d = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))])
    r = u @ d @ vt
    return r, cx - r @ cp


def template(frames):
    """Template of a cluster (frames: F x M x 3), as documented in
    sfit_cluster.h: reference = first frame with every marker, centred on
    its centroid, lab axes; every frame registered to it and mapped back;
    averaged per marker; origin moved to the centroid of the average."""
    import numpy as np
    ok = ~np.isnan(frames).any(axis=(1, 2))
    ref = int(np.argmax(ok))
    t0 = frames[ref] - frames[ref].mean(0)
    acc = np.zeros_like(t0)
    cnt = np.zeros(len(t0))
    for f in range(len(frames)):
        if (~np.isnan(frames[f]).any(axis=1)).sum() < 3:
            continue
        r, t = kabsch(t0, frames[f])
        seen = ~np.isnan(frames[f]).any(axis=1)
        acc[seen] += ((frames[f][seen] - t) @ r)  # R^T (x - t), row-wise
        cnt[seen] += 1
    avg = acc / cnt[:, None]
    return avg - avg.mean(0), ref


def mgdk(markers):
    """Equal-weight MGDK (eq. 220) over a list of N_p x 3 arrays; returns
    (centre, radii, eigenvalues, axis) with the planar (pseudo-inverse)
    solution when planar=True is asked through mgdk_planar."""
    import numpy as np
    a = np.zeros((3, 3))
    b = np.zeros(3)
    for x in markers:
        m = x.mean(0)
        y = x - m
        n = len(x)
        c = y.T @ y / (n - 1)
        s = ((y * y).sum(1)[:, None] * y).sum(0) / (n - 1)
        a += c
        b += c @ m + s / 2
    return np.linalg.solve(a, b), a, b


def mgdk_planar(markers):
    """The hinge solution: pseudo-inverse over the two largest eigen-directions
    of sum C_p, axis = the smallest, centre in the plane through the mean of
    the marker means."""
    import numpy as np
    _, a, b = mgdk(markers)
    w, v = np.linalg.eigh(a)
    axis = v[:, 0]
    c = sum(np.dot(v[:, k], b) / w[k] * v[:, k] for k in (1, 2))
    mbar = np.mean([x.mean(0) for x in markers], axis=0)
    c = c + np.dot(axis, mbar) * axis
    if axis[np.argmax(np.abs(axis))] < 0:
        axis = -axis
    return c, axis
