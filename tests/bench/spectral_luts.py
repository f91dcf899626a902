#!/usr/bin/env python3
"""spectral_luts.py: the sky LUTs' error against the spectral reference, against their cost, per
"spectral_samples" (3 = the RGB model; 6, 9, ... = bands over 380-780 nm baked in groups of three).

A benchmark, not a test: not part of CI. Needs stored references (sky-accuracy --out, default 48x24
panorama and cases) per preset, e.g.
  cpurender sky-accuracy --spp 4096 --out refs/earth-clear
  cpurender sky-accuracy --spp 4096 --seed 2 --out refs/earth-clear-2
  cpurender sky-accuracy --preset reference --spp 4096 --out refs/reference
and --refs earth-clear=refs/earth-clear,refs/earth-clear-2 --refs reference=refs/reference (several
directories of one preset are merged, as sky-accuracy --reference does).

For each sample count and preset it runs
  sky-accuracy --profile P --reference refs/PRESET   (error: mean / p95 luminance, r/g and b/g ratios)
  sky-bench --profile P --threads T                  (cost: the four LUTs' full rebuild, the amortised
      cost with the inputs changing every frame, and the measured LUT work per frame along a
      240-frame path: camera moving, sun setting, atmosphere fixed)
where P is profiles/desktop.json with atmosphere.spectral_samples set, and writes
  OUT/spectral_luts.csv          one row per sample count, preset and case
  OUT/spectral_luts_cost.csv     one row per sample count
  OUT/spectral_luts.png / .svg   error against cost (with python3-matplotlib)

usage: tests/bench/spectral_luts.py --refs PRESET=DIR[,DIR...] [--refs ...] [--samples 3,6,9,12,15]
                                    [--build build] [--threads 2] [--repeat 5] [--out out/spectral]
       tests/bench/spectral_luts.py --chart-only [--out out/spectral]
"""
import argparse, csv, json, os, re, subprocess, sys, tempfile


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode not in (0, 1):  # 1: sky-accuracy's "a case misses its targets"
        sys.exit(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stderr}")
    return r.stdout


ROW = re.compile(r'^\s*([\d.]+)\s+(\d+)\s+\|\s+([\d.]+)%\s+([\d.]+)%\s+\|\s+([\d.]+)%\s+([\d.]+)%\s+\|')


def accuracy(cpurender, profile, preset, refs):
    out = run([cpurender, 'sky-accuracy', '--profile', profile, '--preset', preset, '--reference', refs])
    rows = []
    for line in out.splitlines():
        m = ROW.match(line)
        if m:
            z, alt, mean, p95, rg, bg = m.groups()
            rows.append(dict(zenith=float(z), altitude=int(alt), mean=float(mean), p95=float(p95), rg=float(rg),
                             bg=float(bg)))
    if not rows:
        sys.exit(f'no cases in the sky-accuracy output:\n{out}')
    return rows


def cost(cpurender, profile, threads, repeat):
    out = run([cpurender, 'sky-bench', '--profile', profile, '--threads', str(threads), '--repeat', str(repeat)])
    full = re.search(r'^all four\s+([\d.]+)ms\s+([\d.]+)ms\s+([\d.]+)ms', out, re.M)
    path = re.search(r'measured LUT work per frame \(\d+ threads\): mean ([\d.]+) ms', out)
    if not full or not path:
        sys.exit(f'unexpected sky-bench output:\n{out}')
    return dict(full_ms=float(full.group(2)), amortised_ms=float(full.group(3)), path_ms=float(path.group(1)))


def chart(rows, costs, presets, out):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.6))
    panels = [('mean luminance error, sun zenith 0-90 deg (worst case)', lambda r: r['zenith'] <= 90, 'mean', 2.0),
              ('mean luminance error, sun zenith 95 deg (worst case)', lambda r: r['zenith'] > 90, 'mean', 5.0),
              ('colour error (r/g, b/g), sun zenith 90 deg (worst case)', lambda r: r['zenith'] == 90, 'color', 3.0)]
    for ax, (title, keep, key, target) in zip(axes, panels):
        for preset in presets:
            xs, ys, ns = [], [], []
            for n in sorted(costs):
                sel = [max(r['rg'], r['bg']) if key == 'color' else r[key]
                       for r in rows if r['samples'] == n and r['preset'] == preset and keep(r)]
                if sel:
                    xs.append(costs[n]['path_ms'])
                    ys.append(max(sel))
                    ns.append(n)
            ax.plot(xs, ys, 'o-', label=preset)
            for x, y, n in zip(xs, ys, ns):
                ax.annotate(str(n), (x, y), textcoords='offset points', xytext=(4, 4), fontsize=8)
        ax.axhline(target, color='gray', ls='--', lw=0.8, label=f'target {target:g}%')
        ax.axvline(1.0, color='red', ls=':', lw=0.8, label='1 ms budget')
        ax.set_yscale('log')
        ax.set_xlabel('LUT work per frame along the path (ms, 2 threads)')
        ax.set_ylabel('% against the spectral reference')
        ax.set_title(title, fontsize=9)
        ax.legend(fontsize=7)
    fig.suptitle('Sky LUTs by spectral_samples (labels): error against cost', fontsize=10)
    fig.tight_layout()
    for ext in ('png', 'svg'):
        fig.savefig(os.path.join(out, f'spectral_luts.{ext}'), dpi=110)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--refs', action='append', default=[], metavar='PRESET=DIR[,DIR...]',
                    help='stored references of a preset (repeat per preset)')
    ap.add_argument('--samples', default='3,6,9,12,15')
    ap.add_argument('--build', default='build')
    ap.add_argument('--threads', type=int, default=2)
    ap.add_argument('--repeat', type=int, default=5)
    ap.add_argument('--out', default='out/spectral')
    ap.add_argument('--chart-only', action='store_true', help='redraw the chart from the CSV files in --out')
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    if a.chart_only:
        rows = [dict(r, samples=int(r['samples']), **{k: float(r[k]) for k in r if k not in ('samples', 'preset')})
                for r in csv.DictReader(open(os.path.join(a.out, 'spectral_luts.csv')))]
        costs = {int(r['samples']): {k: float(v) for k, v in r.items() if k != 'samples'}
                 for r in csv.DictReader(open(os.path.join(a.out, 'spectral_luts_cost.csv')))}
        chart(rows, costs, list(dict.fromkeys(r['preset'] for r in rows)), a.out)
        return
    cpurender = os.path.join(a.build, 'cpurender')
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    base = json.load(open(os.path.join(root, 'profiles', 'desktop.json')))
    refs = dict(r.split('=', 1) for r in a.refs)
    presets = list(refs)
    rows, costs = [], {}
    with tempfile.TemporaryDirectory() as tmp:
        for n in [int(s) for s in a.samples.split(',')]:
            profile = json.loads(json.dumps(base))
            profile.setdefault('atmosphere', {})['spectral_samples'] = n
            path = os.path.join(tmp, f'spectral{n}.json')
            json.dump(profile, open(path, 'w'))
            costs[n] = cost(cpurender, path, a.threads, a.repeat)
            for preset in presets:
                for r in accuracy(cpurender, path, preset, refs[preset]):
                    rows.append(dict(samples=n, preset=preset, **r))
            c = costs[n]
            print(f"spectral_samples {n:2d}: full {c['full_ms']:.2f} ms, amortised {c['amortised_ms']:.3f} ms, "
                  f"path {c['path_ms']:.3f} ms/frame", flush=True)
            for preset in presets:
                sel = [r for r in rows if r['samples'] == n and r['preset'] == preset]
                day = [r for r in sel if r['zenith'] <= 90]
                dusk = [r for r in sel if r['zenith'] > 90]
                tw = [r for r in sel if r['zenith'] >= 90]
                print(f"  {preset:12s} 0-90: mean {min(r['mean'] for r in day):.2f}-{max(r['mean'] for r in day):.2f}%"
                      f" p95 <= {max(r['p95'] for r in day):.2f}%;  95: mean {min(r['mean'] for r in dusk):.2f}-"
                      f"{max(r['mean'] for r in dusk):.2f}% p95 <= {max(r['p95'] for r in dusk):.2f}%;  "
                      f"90-95 r/g <= {max(r['rg'] for r in tw):.2f}% b/g <= {max(r['bg'] for r in tw):.2f}%", flush=True)
    with open(os.path.join(a.out, 'spectral_luts.csv'), 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    with open(os.path.join(a.out, 'spectral_luts_cost.csv'), 'w', newline='') as f:
        w = csv.writer(f)
        w.writerow(['samples', 'full_ms', 'amortised_ms', 'path_ms'])
        for n, c in sorted(costs.items()):
            w.writerow([n, c['full_ms'], c['amortised_ms'], c['path_ms']])
    try:
        chart(rows, costs, presets, a.out)
        print(f'wrote {a.out}/spectral_luts.csv, spectral_luts_cost.csv, spectral_luts.png/.svg')
    except ImportError:
        print(f'wrote {a.out}/spectral_luts.csv, spectral_luts_cost.csv (no chart: install python3-matplotlib)')


if __name__ == '__main__':
    main()
