#!/usr/bin/env python3
"""Deadline misses and holds of a wall-clock real-time run with and without monitor viewers
(issue 33, item 2; issue 45, item 5: 100 polling viewers add no hold and at most 20 % more
misses than none).

    python3 bench/monitor/measure_viewers.py [--binary B] [--viewers 0 5 30] [--rounds N]
                                             [--as-is] [--page] [--routes R] [--no-lock]
                                             [--priority P] [--cpu C]

Runs examples/real-time/storey-ats.yaml (10 s at 1024 Hz, wall clock) with `--monitor` once per
viewer count and round, the counts interleaved (0, 100, 0, 100, … with `--viewers 0 100`), so
that a change of the machine's load falls on both. Prints, per run, the exit status, whether it
was held (on misses or on a full journal queue), the ticks, misses, most misses in a row,
wake-up lateness p99/max and compute p99 [µs] and the requests the viewers got answered, from
the run's sidecar (statistics.real_time); then, per viewer count, the misses per 1000 ticks
and the holds over every round.

  --as-is   keep the example's miss policy (hold_after_misses: 10): a viewer that delays the
            loop shows as a hold. Without it the policy is off (hold_after_misses: 0), so that
            a loaded machine records its misses instead of holding.
  --page    the viewers poll as the monitor's page does: one keep-alive connection each,
            /api/state and /api/series alternately every 0.5 s, in a child process at nice 19
            (they stand for browsers on other machines: their own work is kept off this
            machine's cores, so what the run feels is the monitor's side). Without it each
            viewer polls as fast as the server answers, in this process.
  --routes state|series|both   with --page: poll only one of the two (to find which costs).
  --no-lock set the example's lock_memory to false.
  --priority P, --cpu C   set real_time.priority (SCHED_FIFO 1..99) and real_time.cpu (pin the
            stepping thread; the monitor's threads then keep off that CPU), as a lab PC runs.

The run with 0 viewers is the reference of the same invocation: compare the others with it,
not with figures from another machine or another time. Not a test: nothing is asserted.
"""
import argparse
import http.client
import json
import os
import pathlib
import re
import signal
import subprocess
import sys
import tempfile
import threading
import time
import urllib.request

ROOT = pathlib.Path(__file__).resolve().parents[2]


def storey_config(work: pathlib.Path, as_is: bool, lock: bool, priority: int,
                  cpu: int) -> pathlib.Path:
    text = (ROOT / "examples/real-time/storey-ats.yaml").read_text()
    edits = [("file: storey.model.yaml", f"file: {ROOT / 'examples/real-time/storey.model.yaml'}")]
    if not as_is:
        edits.append(("hold_after_misses: 10", "hold_after_misses: 0"))
    if not lock:
        edits.append(("lock_memory: true", "lock_memory: false"))
    if priority or cpu >= 0:
        edits.append(("real_time:\n", f"real_time:\n  priority: {priority}\n  cpu: {cpu}\n"))
    for old, new in edits:
        if old not in text:
            sys.exit(f"measure_viewers: {old!r} not found in storey-ats.yaml; update this script")
        text = text.replace(old, new)
    path = work / "storey.yaml"
    path.write_text(text)
    return path


def poll_fast(port: int, stop: threading.Event, answered: list) -> None:
    while not stop.is_set():
        for route in ("/api/state", "/api/series?since=0"):
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}{route}", timeout=2) as r:
                    r.read()
                    answered.append(1)
            except OSError:
                time.sleep(0.01)


ROUTES = {"both": ("/api/state", "/api/series?since=-1"), "state": ("/api/state",),
          "series": ("/api/series?since=-1",)}


def poll_as_page(port: int, i: int, stop: threading.Event, answered: list, routes: tuple) -> None:
    conn = None
    n = 0
    while not stop.is_set():
        try:
            if conn is None:
                conn = http.client.HTTPConnection("127.0.0.1", port, timeout=5)
            conn.request("GET", routes[n % len(routes)])
            r = conn.getresponse()
            r.read()
            if r.status == 200:
                answered.append(1)
        except (OSError, http.client.HTTPException):
            if conn is not None:
                conn.close()
            conn = None
        n += 1
        stop.wait(0.5 + 0.01 * i)
    if conn is not None:
        conn.close()


def serve_viewers(port: int, viewers: int, routes: str) -> None:
    """The --page viewers' child process: polls until SIGTERM, then prints the answers."""
    stop = threading.Event()
    signal.signal(signal.SIGTERM, lambda *_: stop.set())
    answered: list = []
    threads = [threading.Thread(target=poll_as_page, args=(port, i, stop, answered, ROUTES[routes]),
                                daemon=True) for i in range(viewers)]
    for t in threads:
        t.start()
    while not stop.is_set():
        stop.wait(0.2)
    for t in threads:
        t.join(timeout=6)
    print(len(answered), flush=True)


def measure(binary: str, viewers: int, work: pathlib.Path, config: pathlib.Path, tag: str,
            page: bool, routes: str) -> dict:
    csv = work / f"storey-{tag}.csv"
    log = open(work / f"storey-{tag}.log", "w+")
    proc = subprocess.Popen([binary, "run", str(config), "--clock", "wall", "--out", str(csv),
                             "--quiet", "--overwrite", "--monitor", "127.0.0.1:0",
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
    child = None
    threads = []
    if port and viewers and page:
        child = subprocess.Popen([sys.executable, __file__, "--serve-viewers", str(port),
                                  str(viewers), routes], stdout=subprocess.PIPE, text=True,
                                 preexec_fn=lambda: os.nice(19))
    elif port and viewers:
        threads = [threading.Thread(target=poll_fast, args=(port, stop, answered), daemon=True)
                   for _ in range(viewers)]
    for t in threads:
        t.start()
    status = proc.wait(timeout=120)
    stop.set()
    for t in threads:
        t.join(timeout=5)
    got = len(answered)
    if child is not None:
        child.terminate()
        out, _ = child.communicate(timeout=15)
        got = int(out.split()[-1]) if out.split() else -1  # ended before the viewers started
    meta = csv.with_suffix(".meta.json")
    if not meta.exists():
        log.seek(0)
        sys.exit(f"measure_viewers: the run with {viewers} viewers exited {status} without a "
                 f"sidecar:\n{log.read()}")
    rt = json.loads(meta.read_text())["statistics"]["real_time"]
    return {"viewers": viewers, "exit": status, "held_misses": rt["held_on_misses"],
            "held_queue": rt["held_on_queue"], "ticks": rt["ticks"], "misses": rt["misses"],
            "in_a_row": rt["max_consecutive_misses"], "late_p99_us": rt["late_s"]["p99"] * 1e6,
            "late_max_us": rt["late_s"]["max"] * 1e6,
            "compute_p99_us": rt["compute_s"]["p99"] * 1e6, "answered": got}


def main() -> None:
    if len(sys.argv) == 5 and sys.argv[1] == "--serve-viewers":
        serve_viewers(int(sys.argv[2]), int(sys.argv[3]), sys.argv[4])
        return
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--binary", default=str(ROOT / "build/release/apps/hybridtest/hybridtest"))
    p.add_argument("--viewers", type=int, nargs="+", default=[0, 5, 30])
    p.add_argument("--rounds", type=int, default=1)
    p.add_argument("--as-is", action="store_true")
    p.add_argument("--page", action="store_true")
    p.add_argument("--routes", choices=sorted(ROUTES), default="both")
    p.add_argument("--no-lock", action="store_true")
    p.add_argument("--priority", type=int, default=0)
    p.add_argument("--cpu", type=int, default=-1)
    a = p.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(tmp)
        config = storey_config(work, a.as_is, not a.no_lock, a.priority, a.cpu)
        for r in range(a.rounds):
            for n in a.viewers:
                row = measure(a.binary, n, work, config, f"{r}-{n}", a.page, a.routes)
                row["round"] = r + 1
                rows.append(row)
                print(json.dumps(row), flush=True)
    load = pathlib.Path("/proc/loadavg").read_text().split()[0]
    print(f"\n{'round':>5} {'viewers':>7} {'exit':>4} {'held':>5} {'ticks':>6} {'misses':>6} "
          f"{'in row':>6} {'late p99':>9} {'late max':>9} {'comp p99':>9} {'answered':>8}   [µs]")
    for r in rows:
        held = "misses" if r["held_misses"] else "queue" if r["held_queue"] else "no"
        print(f"{r['round']:>5} {r['viewers']:>7} {r['exit']:>4} {held:>5} {r['ticks']:>6} "
              f"{r['misses']:>6} {r['in_a_row']:>6} {r['late_p99_us']:>9.1f} "
              f"{r['late_max_us']:>9.1f} {r['compute_p99_us']:>9.1f} {r['answered']:>8}")
    print(f"\nper viewer count, over {a.rounds} round(s) (load average at the end {load}):")
    for n in a.viewers:
        mine = [r for r in rows if r["viewers"] == n]
        ticks = sum(r["ticks"] for r in mine)
        misses = sum(r["misses"] for r in mine)
        holds = sum(1 for r in mine if r["held_misses"] or r["held_queue"])
        print(f"  {n:>4} viewers: {misses} misses in {ticks} ticks "
              f"({1000.0 * misses / max(ticks, 1):.2f} per 1000), {holds} of {len(mine)} held")


if __name__ == "__main__":
    main()
