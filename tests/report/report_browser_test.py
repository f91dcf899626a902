"""The report in headless Chromium: generated from the fixtures (no rendering), each page must load with
no console message and every <img> decoded (naturalWidth > 0). A corrupted copy of a page, with a
broken image and a script error, must fail both checks, so a check that cannot fail is caught.

usage: report_browser_test.py OUTDIR     exit 0: pass, 1: fail, 77: skipped (no chromium)
"""
import re
import shutil
import subprocess
import sys
from pathlib import Path

from report_paths import DATA, TOOLS

# The report's inline script writes decoded/total images on <body> after the load event.
DECODED = re.compile(r'<body[^>]*\sdata-images-decoded="(\d+)/(\d+)"')
CONSOLE = re.compile(r'^.*(:CONSOLE[(:]|Uncaught).*$', re.M)


def chromium():
    return shutil.which('chromium') or shutil.which('chromium-browser')


def load(browser, page):
    """(decoded images, total images, console lines) of a page after Chromium loaded it."""
    # Root in CI: no sandbox. --virtual-time-budget lets the load event fire before the DOM is dumped.
    run = subprocess.run(['timeout', '60', browser, '--headless', '--no-sandbox', '--disable-gpu',
                          '--enable-logging=stderr', '--v=0', '--virtual-time-budget=5000', '--dump-dom',
                          page.resolve().as_uri()], capture_output=True, text=True)
    if run.returncode != 0:
        raise RuntimeError(f'chromium exited {run.returncode} on {page}:\n{run.stderr[-3000:]}')
    match = DECODED.search(run.stdout)
    if not match:
        raise RuntimeError(f'{page}: no data-images-decoded on <body>: the check script did not run')
    return int(match.group(1)), int(match.group(2)), CONSOLE.findall(run.stderr)


def corrupted_copy(page):
    """The page with its first image's PNG data cut short and a script that throws."""
    html = page.read_text()
    html = re.sub(r'(data:image/png;base64,)[A-Za-z0-9+/]{64}', r'\1', html, count=1)
    html = html.replace('</body>', '<script>undefinedReportFunction();</script></body>')
    bad = page.with_name('corrupted_copy.html')
    bad.write_text(html)
    return bad


def main(out):
    browser = chromium()
    if not browser:
        print('skipped: chromium is not installed (tests/setup_debian.sh installs it)')
        return 77
    shutil.rmtree(out, ignore_errors=True)
    run = subprocess.run([sys.executable, str(TOOLS / 'cpurender_report.py'), '--title', 'Browser test',
                          '--sweep', str(DATA / 'sweep_profiles'), '--sweep', str(DATA / 'sweep_froxels'),
                          '--timing', str(DATA / 'report.json'), '--plan', str(DATA / 'plan.json'),
                          '--out', str(out)], capture_output=True, text=True, timeout=120)
    if run.returncode != 0:
        print(f'FAIL: the report was not generated:\n{run.stderr}')
        return 1
    pages = sorted(out.glob('*_report.html'))
    failures = [] if pages else ['no page was written']
    for page in pages:
        decoded, total, console = load(browser, page)
        print(f'{page.name}: {decoded}/{total} images decoded, {len(console)} console lines')
        if total == 0 or decoded != total:
            failures.append(f'{page.name}: {decoded} of {total} images decoded')
        failures += [f'{page.name}: console: {line}' for line in console]
    decoded, total, console = load(browser, corrupted_copy(pages[0])) if pages else (0, 0, [])
    print(f'corrupted copy: {decoded}/{total} images decoded, {len(console)} console lines')
    if pages and decoded == total:
        failures.append('the corrupted copy passed the image check')
    if pages and not console:
        failures.append('the corrupted copy\'s script error was not seen on the console')
    for f in failures:
        print(f'FAIL: {f}')
    return 1 if failures else 0


if __name__ == '__main__':
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(main(Path(sys.argv[1])))
