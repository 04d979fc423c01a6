#!/usr/bin/env python3
"""Runs every bench/bench_*.py in turn (make bench)."""
import glob
import os
import subprocess
import sys

here = os.path.dirname(os.path.abspath(__file__))
status = 0
for path in sorted(glob.glob(os.path.join(here, "bench_*.py"))):
    print(f"== {os.path.basename(path)}", flush=True)
    status |= subprocess.run([sys.executable, path]).returncode
sys.exit(status)
