# Makes the platformer's tileset and level (run once; the files are committed):
# assets/maps/tiles.png (8 tiles of 16 x 16 pixels in a row of 4 by 2),
# assets/maps/tiles.tsx (the tileset) and assets/maps/level.tmx (the level).
import struct, zlib

T = 16
COLUMNS, ROWS = 4, 2

def tile_pixel(tile, x, y):
    """The colour of pixel (x, y) of tile `tile` (0-7), RGBA."""
    if tile == 0:  # grass over soil
        if y < 4:
            return (72, 170, 60, 255) if (x + y) % 5 else (96, 196, 80, 255)
        return (120, 80, 48, 255) if (x * 7 + y * 3) % 11 else (96, 64, 40, 255)
    if tile == 1:  # soil
        return (120, 80, 48, 255) if (x * 7 + y * 3) % 11 else (96, 64, 40, 255)
    if tile == 2:  # brick
        mortar = y % 8 == 7 or (x + (4 if (y // 8) % 2 else 0)) % 8 == 7
        return (150, 150, 160, 255) if mortar else (176, 72, 56, 255)
    if tile == 3:  # spikes
        column = x % 8
        height = 2 * min(column, 7 - column) + 2
        return (210, 210, 220, 255) if T - 1 - y < height * 2 else (0, 0, 0, 0)
    if tile == 4:  # a coin
        d = ((x - 7.5) ** 2 + (y - 7.5) ** 2) ** 0.5
        if d < 5.5:
            return (250, 210, 60, 255) if d < 4.5 else (200, 150, 30, 255)
        return (0, 0, 0, 0)
    if tile == 5:  # a flag on its pole
        if x in (3, 4):
            return (230, 230, 230, 255)
        if 5 <= x <= 14 and 1 <= y <= 8 - abs(x - 9) // 3:
            return (220, 40, 60, 255)
        return (0, 0, 0, 0)
    if tile == 6:  # a wooden platform (the ferry)
        if y < 6:
            return (180, 130, 70, 255) if x % 4 else (140, 96, 50, 255)
        return (0, 0, 0, 0)
    # 7: an arrow pointing right: the top-left half is darker, to show flips
    if abs(y - 7.5) < (x + 1) / 2:
        return (80, 120, 230, 255) if x + y < T else (160, 190, 250, 255)
    return (0, 0, 0, 0)

def png(path, width, height, pixel):
    rows = b''.join(b'\x00' + b''.join(bytes(pixel(x, y)) for x in range(width)) for y in range(height))
    chunk = lambda kind, data: struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
    header = struct.pack('>IIBBBBB', width, height, 8, 6, 0, 0, 0)
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', header) + chunk(b'IDAT', zlib.compress(rows, 9)) + chunk(b'IEND', b''))

png('assets/maps/tiles.png', COLUMNS * T, ROWS * T,
    lambda x, y: tile_pixel((y // T) * COLUMNS + x // T, x % T, y % T))

open('assets/maps/tiles.tsx', 'w').write(f'''<?xml version="1.0" encoding="UTF-8"?>
<tileset version="1.10" tiledversion="1.10.2" name="tiles" tilewidth="{T}" tileheight="{T}" tilecount="{COLUMNS * ROWS}" columns="{COLUMNS}">
 <image source="tiles.png" width="{COLUMNS * T}" height="{ROWS * T}"/>
</tileset>
''')

# The level's solid ground: '#' grass, '=' soil, 'B' brick, '.' nothing.
# Row 0 is the top. A gap to jump, a pillar to climb, a drop onto a
# platform, a pit of spikes that the ferry crosses (docked at x 21 and x
# 28), two steps up to the flag.
LEVEL = [
    "........................................",
    "........................................",
    "..............BBB.......................",
    "........................................",
    "........................................",
    "........................................",
    "........................................",
    "..........BB...........................B",
    "..........BB.......................#####",
    "#######...BB.....####..........#########",
    "=======...==.....====..........=========",
    "=======...==.....=======================",
]
GID = {'.': 0, '#': 1, '=': 2, 'B': 3}
rows = [','.join(str(GID[c]) for c in row) for row in LEVEL]
csv = ',\n'.join(rows)
width, height = len(LEVEL[0]), len(LEVEL)
# Decor: an arrow on the first platform, and the same arrow flipped
# horizontally (bit 31), vertically (bit 30) and diagonally (bit 29).
decor = [[0] * width for _ in range(height)]
decor[8][1] = 8
decor[8][2] = 8 | 0x80000000
decor[8][3] = 8 | 0x40000000
decor[8][4] = 8 | 0x20000000
decor[7][38] = 6
# Spikes along the pit (drawn; the objects' "spikes" is their sensor).
for x in range(21, 31):
    decor[10][x] = 4
decor_csv = ',\n'.join(','.join(str(g) for g in row) for row in decor)
open('assets/maps/level.tmx', 'w').write(f'''<?xml version="1.0" encoding="UTF-8"?>
<map version="1.10" tiledversion="1.10.2" orientation="orthogonal" renderorder="right-down" width="{width}" height="{height}" tilewidth="{T}" tileheight="{T}" infinite="0" nextlayerid="4" nextobjectid="12">
 <tileset firstgid="1" source="tiles.tsx"/>
 <layer id="1" name="ground" width="{width}" height="{height}">
  <properties>
   <property name="solid" type="bool" value="true"/>
  </properties>
  <data encoding="csv">
{csv}
</data>
 </layer>
 <layer id="2" name="decor" width="{width}" height="{height}">
  <data encoding="csv">
{decor_csv}
</data>
 </layer>
 <objectgroup id="3" name="objects">
  <object id="1" name="player" type="spawn" x="40" y="136">
   <point/>
  </object>
  <object id="2" name="coin" type="coin" x="136" y="88" width="16" height="16"/>
  <object id="3" name="coin" type="coin" x="176" y="96" width="16" height="16"/>
  <object id="4" name="coin" type="coin" x="296" y="128" width="16" height="16"/>
  <object id="5" name="spikes" type="hazard" x="336" y="164" width="160" height="12"/>
  <object id="6" name="flag" type="goal" x="608" y="96" width="16" height="32">
   <properties>
    <property name="next" value="level2.tmx"/>
   </properties>
  </object>
  <object id="7" name="ferry" type="platform" x="336" y="144" width="48" height="8">
   <properties>
    <property name="speed" type="float" value="1.5"/>
    <property name="travel" type="int" value="7"/>
   </properties>
  </object>
 </objectgroup>
</map>
''')

# The hero: six frames of 16 x 24 in a row: standing, four of a run, a jump.
HW, HH = 16, 24
def hero_pixel(frame, x, y):
    skin, shirt, trousers, hair = (240, 200, 160, 255), (60, 110, 220, 255), (50, 50, 70, 255), (90, 60, 30, 255)
    if 2 <= y <= 7 and 5 <= x <= 10:  # the head, facing right
        if y <= 3:
            return hair
        return (20, 20, 20, 255) if (x == 9 and y == 5) else skin
    if 8 <= y <= 15 and 5 <= x <= 10:  # the body
        return shirt
    if 16 <= y <= 23:  # the legs: apart by the frame
        spread = [0, 2, 3, 2, 0, 3][frame]
        lift = [0, 0, 1, 0, 0, 2][frame]
        left, right = 6 - spread // 2, 9 + spread // 2
        if frame in (2, 3):
            left, right = left + 1, right - 1
        if x in (left, left + 1) and y <= 23 - (lift if frame % 2 else 0):
            return trousers
        if x in (right - 1, right) and y <= 23 - lift:
            return trousers
    if 9 <= y <= 13 and x in (4, 11) and frame != 5:  # arms
        return skin
    if frame == 5 and y in (6, 7) and x in (3, 12):  # arms up in a jump
        return skin
    return (0, 0, 0, 0)

png('assets/sprites/hero.png', 6 * HW, HH, lambda x, y: hero_pixel(x // HW, x % HW, y))
