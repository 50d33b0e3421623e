#!/usr/bin/env python3
"""Deadline misses of a wall-clock real-time run with 0, 5 and 30 monitor viewers (issue 33,
item 2: the stepping thread never shares its core's time with the server's threads).

    python3 bench/monitor/measure_viewers.py [BINARY] [VIEWERS ...]

Runs examples/real-time/storey-ats.yaml (10 s at 1024 Hz, wall clock) with `--monitor` once per
viewer count (default 0 5 30), its miss policy off (`hold_after_misses: 0`, so that a loaded
machine records its misses instead of holding). Each viewer polls /api/state and /api/series
as fast as the server answers. Prints, per run, the ticks, misses, wake-up lateness p50/p99/max
[µs], compute p99 [µs] and the requests the viewers got answered, from the run's sidecar
(statistics.real_time). The run with 0 viewers is the reference of the same invocation: compare
the others with it, not with figures from another machine or another time.
"""
import json
import pathlib
import re
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

ROOT = pathlib.Path(__file__).resolve().parents[2]


def storey_config(work: pathlib.Path) -> pathlib.Path:
    text = (ROOT / "examples/real-time/storey-ats.yaml").read_text()
    for old, new in (("file: storey.model.yaml",
                      f"file: {ROOT / 'examples/real-time/storey.model.yaml'}"),
                     ("hold_after_misses: 10", "hold_after_misses: 0")):
        if old not in text:
            sys.exit(f"measure_viewers: {old!r} not found in storey-ats.yaml; update this script")
        text = text.replace(old, new)
    path = work / "storey.yaml"
    path.write_text(text)
    return path


def poll(port: int, stop: threading.Event, answered: list) -> None:
    while not stop.is_set():
        for route in ("/api/state", "/api/series?since=0"):
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}{route}", timeout=2) as r:
                    r.read()
                    answered.append(1)
            except OSError:
                time.sleep(0.01)


def measure(binary: str, viewers: int, work: pathlib.Path) -> dict:
    csv = work / f"storey-{viewers}.csv"
    log = open(work / f"storey-{viewers}.log", "w+")
    proc = subprocess.Popen([binary, "run", str(storey_config(work)), "--clock", "wall", "--out",
                             str(csv), "--quiet", "--overwrite", "--monitor", "127.0.0.1:0",
                             "--monitor-no-token"], stdout=log, stderr=log)
    port = 0
    deadline = time.monotonic() + 30
    while not port and time.monotonic() < deadline and proc.poll() is None:
        time.sleep(0.01)
        log.seek(0)
        m = re.search(r"monitor at http://127\.0\.0\.1:(\d+)/", log.read())
        port = int(m.group(1)) if m else 0
    stop = threading.Event()
    answered: list = []
    threads = [threading.Thread(target=poll, args=(port, stop, answered), daemon=True)
               for _ in range(viewers if port else 0)]
    for t in threads:
        t.start()
    status = proc.wait(timeout=120)
    stop.set()
    for t in threads:
        t.join(timeout=5)
    if status != 0:
        log.seek(0)
        sys.exit(f"measure_viewers: the run with {viewers} viewers exited {status}:\n{log.read()}")
    rt = json.loads(csv.with_suffix(".meta.json").read_text())["statistics"]["real_time"]
    return {"viewers": viewers, "ticks": rt["ticks"], "misses": rt["misses"],
            "late_p50_us": rt["late_s"]["p50"] * 1e6, "late_p99_us": rt["late_s"]["p99"] * 1e6,
            "late_max_us": rt["late_s"]["max"] * 1e6,
            "compute_p99_us": rt["compute_s"]["p99"] * 1e6, "answered": len(answered)}


def main() -> None:
    binary = sys.argv[1] if len(sys.argv) > 1 else str(ROOT / "build/release/apps/hybridtest/hybridtest")
    counts = [int(v) for v in sys.argv[2:]] or [0, 5, 30]
    with tempfile.TemporaryDirectory() as tmp:
        rows = [measure(binary, n, pathlib.Path(tmp)) for n in counts]
    print(f"{'viewers':>7} {'ticks':>6} {'misses':>6} {'late p50':>9} {'late p99':>9} "
          f"{'late max':>9} {'compute p99':>11} {'answered':>8}   [µs]")
    for r in rows:
        print(f"{r['viewers']:>7} {r['ticks']:>6} {r['misses']:>6} {r['late_p50_us']:>9.1f} "
              f"{r['late_p99_us']:>9.1f} {r['late_max_us']:>9.1f} {r['compute_p99_us']:>11.1f} "
              f"{r['answered']:>8}")


if __name__ == "__main__":
    main()
