#!/usr/bin/env python3
"""sky_banding.py: banding of the mobile profile's twilight and night sky against desktop's.

A benchmark, not a test: not part of CI; it prints a table.

Renders an all-sky view (camera at 300 m looking 40 deg up towards the sun's azimuth, 60 deg vertical
field of view: elevations 10-70 deg, nothing but sky) of the default scene's atmosphere with the sun
below the horizon at zenith 92, 94 and 96 deg (dusk) and 105 deg (night), under profiles/desktop.json
and profiles/mobile.json at the same resolution, each exposed for its sky, and measures on the 8-bit
frames:
  max step   the largest difference (any channel, in 8-bit codes) between vertically adjacent pixels,
             over every column: a band edge shows as a step larger than the gradient's own;
  levels     the number of distinct 8-bit green values down the middle column (fewer levels across
             the same gradient: coarser bands).
Target (issue: mobile profile): mobile's max step <= desktop's + 1 code.

usage: tests/bench/sky_banding.py [--build DIR] [--size WxH] [--out DIR]
"""
import argparse, json, os, struct, subprocess, sys, zlib


def read_png(path):
    """8-bit RGB/RGBA non-interlaced PNG -> (width, height, rows of bytes, channels)."""
    data = open(path, 'rb').read()
    assert data[:8] == b'\x89PNG\r\n\x1a\n', path
    pos, idat, width = 8, b'', 0
    while pos < len(data):
        length, kind = struct.unpack('>I4s', data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b'IHDR':
            width, height, depth, color = struct.unpack('>IIBB', body[:10])
            assert depth == 8 and color in (2, 6), 'only 8-bit RGB/RGBA'
            channels = 3 if color == 2 else 4
        elif kind == b'IDAT':
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, prev = [], bytearray(stride)
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b = prev[i]
            c = prev[i - channels] if i >= channels else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(line)
        prev = line
    return width, height, rows, channels


def banding(path):
    w, h, rows, ch = read_png(path)
    step = 0
    for y in range(h - 1):
        for x in range(w):
            for c in range(3):
                step = max(step, abs(rows[y + 1][x * ch + c] - rows[y][x * ch + c]))
    levels = len({rows[y][(w // 2) * ch + 1] for y in range(h)})
    return step, levels


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--build', default='build')
    ap.add_argument('--size', default='480x270')
    ap.add_argument('--out', default='out/sky_banding')
    args = ap.parse_args()
    root = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '..')
    os.chdir(root)
    os.makedirs(args.out, exist_ok=True)
    exe = os.path.join(args.build, 'cpurender')
    # Sun zenith -> exposure (EV100) that puts the sky mid-range.
    cases = [(92, 9), (94, 6), (96, 3), (105, -5)]
    print(f'| sun zenith | desktop max step | mobile max step | desktop levels | mobile levels | within target |')
    print('|---:|---:|---:|---:|---:|---|')
    ok = True
    for zenith, ev in cases:
        scene = {"gltf": "default.glb",
                 "camera": {"position": [0, 300, 0], "target": [0, 300 + 839.1, -1000], "vfov_deg": 60},
                 "sun": {"azimuth_deg": 180, "elevation_deg": 90 - zenith, "illuminance": 110000},
                 "exposure_ev100": ev, "frames": 1, "atmosphere": {"preset": "earth-clear"}}
        path = os.path.join(args.out, f'dusk_{zenith}.json')
        json.dump(scene, open(path, 'w'))
        result = {}
        for profile in ('desktop', 'mobile'):
            frame_dir = os.path.join(args.out, f'{zenith}.{profile}')
            subprocess.run([exe, 'render', path, '--profile', f'profiles/{profile}.json', '--resolution', args.size,
                            '--out', frame_dir, '--quiet', '--no-trace'], check=True)
            result[profile] = banding(os.path.join(frame_dir, 'frame_0000.png'))
        (ds, dl), (ms, ml) = result['desktop'], result['mobile']
        good = ms <= ds + 1
        ok = ok and good
        print(f'| {zenith} deg | {ds} | {ms} | {dl} | {ml} | {"yes" if good else "NO"} |')
    return 0 if ok else 1


if __name__ == '__main__':
    sys.exit(main())
