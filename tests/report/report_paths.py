"""Paths shared by the report tests; importing it puts tools/report on sys.path, so the tests also run
by hand (cd tests/report && /usr/bin/python3 -m unittest) without CTest's PYTHONPATH."""
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
TOOLS = REPO / 'tools' / 'report'
DATA = Path(__file__).resolve().parent / 'data'
if str(TOOLS) not in sys.path:
    sys.path.insert(0, str(TOOLS))
