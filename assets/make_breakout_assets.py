# Makes Breakout's sounds and ball sprite (run once; the files are committed).
import math, struct, wave, zlib

def blip(path, parts, rate=22050):
    """parts: list of (seconds, start_hz, end_hz, volume); a decaying tone each."""
    samples = []
    for seconds, f0, f1, volume in parts:
        n = int(seconds * rate)
        phase = 0.0
        for i in range(n):
            t = i / n
            f = f0 + (f1 - f0) * t
            phase += 2 * math.pi * f / rate
            envelope = min(1.0, i / (0.004 * rate)) * (1 - t) ** 2
            square = 1.0 if math.sin(phase) >= 0 else -1.0
            samples.append(volume * envelope * (0.6 * math.sin(phase) + 0.4 * square))
    with wave.open(path, 'wb') as w:
        w.setnchannels(1); w.setsampwidth(2); w.setframerate(rate)
        w.writeframes(b''.join(struct.pack('<h', int(max(-1, min(1, s)) * 32000)) for s in samples))

blip('assets/sounds/brick.wav', [(0.09, 880, 1320, 0.5)])
blip('assets/sounds/paddle.wav', [(0.07, 440, 520, 0.5)])
blip('assets/sounds/lost.wav', [(0.18, 392, 262, 0.5), (0.3, 262, 131, 0.5)])

def png(path, size, pixel):
    rows = b''.join(b'\x00' + b''.join(bytes(pixel(x, y)) for x in range(size)) for y in range(size))
    chunk = lambda kind, data: struct.pack('>I', len(data)) + kind + data + struct.pack('>I', zlib.crc32(kind + data) & 0xffffffff)
    header = struct.pack('>IIBBBBB', size, size, 8, 6, 0, 0, 0)
    open(path, 'wb').write(b'\x89PNG\r\n\x1a\n' + chunk(b'IHDR', header) + chunk(b'IDAT', zlib.compress(rows, 9)) + chunk(b'IEND', b''))

def ball(x, y, size=32):
    # A white ball lit from the upper left, with a soft rim.
    cx = cy = (size - 1) / 2
    r = size / 2 - 0.5
    dx, dy = (x - cx) / r, (y - cy) / r
    d = math.hypot(dx, dy)
    if d > 1.0:
        return (0, 0, 0, 0)
    alpha = int(255 * min(1.0, (1.0 - d) * r))
    light = max(0.0, 1 - math.hypot(dx + 0.35, dy + 0.35) / 1.35)
    shade = int(150 + 105 * light)
    return (shade, shade, min(255, shade + 8), alpha)

png('assets/sprites/ball.png', 32, ball)
