#!/usr/bin/env python3
"""Prints a PNG's size and the RGBA of pixels, for cli/tests/driver.sh (8-bit RGBA or RGB
PNGs, as softpbr writes them; no library needed):

  png_pixel.py FILE X,Y [X,Y ...]  ->  "WIDTHxHEIGHT" then "R G B A" for each pixel
"""
import struct
import sys
import zlib

data = open(sys.argv[1], 'rb').read()
assert data[:8] == b'\x89PNG\r\n\x1a\n', 'not a PNG'
pos, idat, ihdr = 8, b'', None
while pos < len(data):
    n, kind = struct.unpack('>I4s', data[pos:pos + 8])
    body = data[pos + 8:pos + 8 + n]
    if kind == b'IHDR':
        ihdr = struct.unpack('>IIBBBBB', body)
    elif kind == b'IDAT':
        idat += body
    pos += 12 + n
w, h, depth, colour, _, _, interlace = ihdr
assert depth == 8 and colour in (2, 6) and interlace == 0, ihdr
bpp = 4 if colour == 6 else 3
raw, rows, prev = zlib.decompress(idat), [], bytearray(w * bpp)
stride = w * bpp + 1
for y in range(h):
    f, line = raw[y * stride], bytearray(raw[y * stride + 1:(y + 1) * stride])
    for i in range(len(line)):
        a = line[i - bpp] if i >= bpp else 0
        b = prev[i]
        c = prev[i - bpp] if i >= bpp else 0
        if f == 1:
            line[i] = (line[i] + a) & 255
        elif f == 2:
            line[i] = (line[i] + b) & 255
        elif f == 3:
            line[i] = (line[i] + (a + b) // 2) & 255
        elif f == 4:
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    rows.append(line)
    prev = line
print(f'{w}x{h}')
for xy in sys.argv[2:]:
    x, y = (int(v) for v in xy.split(','))
    px = rows[y][x * bpp:(x + 1) * bpp]
    print(' '.join(str(v) for v in (list(px) + [255] * (4 - bpp))))
