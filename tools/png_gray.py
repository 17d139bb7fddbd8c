#!/usr/bin/env python3
# tools/png_gray.py: rewrites 8-bit RGB(A) PNGs (what `mimetic render` writes) as grayscale, about a
# quarter the bytes, for the pictures in docs/ (tools/make-library.sh). Standard library only.
#   python3 tools/png_gray.py A.png B.png ...
import struct, sys, zlib
def read_png(path):
    data = open(path, 'rb').read()
    assert data[:8] == b'\x89PNG\r\n\x1a\n'
    pos, idat, w, h, ct = 8, b'', 0, 0, 0
    while pos < len(data):
        n, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        if kind == b'IHDR':
            w, h, depth, ct = struct.unpack('>IIBB', body[:10])
            assert depth == 8 and ct in (2, 6)
        elif kind == b'IDAT':
            idat += body
        pos += 12 + n
    bpp = 3 if ct == 2 else 4
    raw, stride, rows, prev = zlib.decompress(idat), w * bpp, [], bytearray(w * bpp)
    for y in range(h):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - bpp] if i >= bpp else 0
            b, c = prev[i], (prev[i - bpp] if i >= bpp else 0)
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c; pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line); prev = line
    return w, h, bpp, rows
def write_gray(path, w, h, bpp, rows):
    out, prev = bytearray(), bytearray(w)
    for line in rows:
        g = bytearray((299 * line[x * bpp] + 587 * line[x * bpp + 1] + 114 * line[x * bpp + 2]) // 1000 for x in range(w))
        out += b'\x02' + bytes((g[x] - prev[x]) & 255 for x in range(w))  # filter "up"
        prev = g
    def chunk(kind, body):
        return struct.pack('>I', len(body)) + kind + body + struct.pack('>I', zlib.crc32(kind + body) & 0xffffffff)
    png = b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', struct.pack('>IIBBBBB', w, h, 8, 0, 0, 0, 0))
    png += chunk(b'IDAT', zlib.compress(bytes(out), 9)) + chunk(b'IEND', b'')
    open(path + '.tmp', 'wb').write(png)
    import os; os.replace(path + '.tmp', path)
for p in sys.argv[1:]:
    write_gray(p, *read_png(p))
