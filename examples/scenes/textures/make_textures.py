# examples/scenes/textures/make_textures.py — writes the textures of textured.json, drawn
# procedurally (no source images, so no licence to carry): a checker, and bricks in glTF's
# three maps — base colour (sRGB), normal (tangent space, +Y up) and ORM (occlusion in R,
# roughness in G, metallic in B: one file for the occlusion and metallic-roughness slots).
# Python's standard library only; the same bytes on every run.
# Run from this folder: python3 make_textures.py
import math, struct, zlib

def png(name, w, h, texel):
    """An 8-bit RGB PNG of w × h whose texel (x, y) is texel(x, y) → (r, g, b), row 0 on top."""
    rows = b"".join(b"\0" + bytes(c for x in range(w) for c in texel(x, y)) for y in range(h))
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    with open(name, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(rows, 9)) + chunk(b"IEND", b""))

def checker(x, y):
    return (205, 205, 200) if (x // 8 + y // 8) % 2 == 0 else (60, 62, 66)

# Bricks: a running bond of 32 × 16 texel bricks, 2 texels of mortar, a 2-texel bevel; the
# texture tiles (128 = 4 bricks across, 8 rows).
W, BW, BH, MORTAR, BEVEL = 128, 32, 16, 2, 2

def brick_at(x, y):
    """(brick id, distance in texels from the brick's edge; ≤ 0 in the mortar)."""
    row = y // BH
    xs = (x + (BW // 2) * (row % 2)) % W
    col = xs // BW
    u, v = xs % BW, y % BH
    edge = min(u, BW - 1 - u, v, BH - 1 - v) - MORTAR // 2 + 1
    return (row * 7 + col * 3) % 5, edge

def height(x, y):
    _, edge = brick_at(x % W, y % W)
    return max(0.0, min(1.0, edge / BEVEL))

def bricks_color(x, y):
    brick, edge = brick_at(x, y)
    if edge <= 0:
        return (150, 146, 138)
    tint = [(150, 62, 44), (138, 58, 40), (160, 72, 50), (128, 52, 38), (146, 66, 48)][brick]
    return tint

def bricks_normal(x, y):
    # n ∝ (−∂h/∂x, +∂h/∂row, 1 / strength): rows grow down the image, +Y is up.
    dx = (height(x + 1, y) - height(x - 1, y)) / 2
    dy = (height(x, y + 1) - height(x, y - 1)) / 2
    n = (-dx, dy, 0.5)
    l = math.sqrt(sum(c * c for c in n))
    return tuple(int(round((c / l * 0.5 + 0.5) * 255)) for c in n)

def bricks_orm(x, y):
    _, edge = brick_at(x, y)
    mortar = edge <= 0
    return (150 if mortar else 255, 245 if mortar else 190, 0)

png("checker.png", 64, 64, checker)
png("bricks_color.png", W, W, bricks_color)
png("bricks_normal.png", W, W, bricks_normal)
png("bricks_orm.png", W, W, bricks_orm)
