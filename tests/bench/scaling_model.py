#!/usr/bin/env python3
"""scaling_model.py: how far each pass of a frame can scale, from a 1-thread trace.

A benchmark aid, not a test. Render with one thread and a trace:

    cpurender render SCENE --threads 1 --frames 8 --format none --out out/scaling
    tests/bench/scaling_model.py out/scaling/trace.json --threads 2,4,8,16

For every pass of every frame (after --skip warm-up frames) the trace gives the pass's wall time and
its parallel_for chunks (job events inside it). The part of the pass outside any chunk is serial. For
N threads the model schedules each parallel_for's chunks in order on N workers, as the job system's
FIFO queue does (each chunk to the first free worker), and adds the serial part:

    pass(N) = serial + sum over its parallel_fors of the makespan of their chunks on N workers

Passes are taken one after another (passes that the frame graph runs concurrently are not overlapped,
so the frame prediction errs slow by their overlap). Chunks keep their 1-thread durations: the model
knows nothing of memory bandwidth, shared caches or queue contention, so a measured time above the
prediction is what those cost. Prints per pass (median over frames): 1-thread ms, serial ms, chunk
count, longest chunk, predicted ms at each N and the speedup they allow, then the frame.
"""
import argparse
import heapq
import json
import statistics
import sys


def makespan(durations, workers):
    """FIFO list scheduling: each chunk, in order, starts on the earliest free worker."""
    free = [0.0] * workers
    end = 0.0
    for d in durations:
        start = heapq.heappop(free)
        heapq.heappush(free, start + d)
        end = max(end, start + d)
    return end


def top_level(jobs):
    """Jobs not inside another job of the list (sorted by start)."""
    out = []
    reach = -1.0
    for j in sorted(jobs, key=lambda j: (j["ts"], -j["dur"])):
        if j["ts"] >= reach:
            out.append(j)
            reach = j["ts"] + j["dur"]
    return out


def groups(chunks):
    """Consecutive chunks of one name: one parallel_for."""
    out = []
    for c in chunks:
        if out and out[-1][0] == c["name"]:
            out[-1][1].append(c["dur"])
        else:
            out.append((c["name"], [c["dur"]]))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("trace", help="trace.json of a --threads 1 run")
    ap.add_argument("--threads", default="2,4,8,16", help="thread counts to predict (default 2,4,8,16)")
    ap.add_argument("--skip", type=int, default=2, help="warm-up frames left out (default 2)")
    ap.add_argument("--detail", action="store_true", help="also list each pass's parallel_fors")
    a = ap.parse_args()
    threads = [int(t) for t in a.threads.split(",")]
    events = json.load(open(a.trace))["traceEvents"]
    frames = [e for e in events if e.get("cat") == "frame"]
    passes = [e for e in events if e.get("cat") == "pass"]
    jobs = [e for e in events if e.get("cat") == "job"]
    if len({j["tid"] for j in jobs}) > 1:
        sys.exit("scaling_model.py: the trace has jobs on several workers; render it with --threads 1")
    frames = sorted(frames, key=lambda f: f["ts"])[a.skip:]
    if not frames:
        sys.exit("scaling_model.py: no frames after the warm-up ones")

    per_pass = {}  # name -> list of (ms1, serial, chunks, longest, {N: ms})
    per_loop = {}  # (pass, parallel_for) -> list of (ms1, chunks, longest, {N: ms})
    frame_rows = []
    for f in frames:
        f0, f1 = f["ts"], f["ts"] + f["dur"]
        total1, totalN = 0.0, {n: 0.0 for n in threads}
        for p in (p for p in passes if f0 <= p["ts"] < f1):
            p0, p1 = p["ts"], p["ts"] + p["dur"]
            # The pass's own graph job spans it; its chunks are the jobs inside that.
            inside = [j for j in jobs if p0 <= j["ts"] and j["ts"] + j["dur"] <= p1 + 1.0 and j["dur"] < p["dur"] * 0.999]
            chunks = top_level(inside)
            work = sum(c["dur"] for c in chunks)
            serial = max(0.0, p["dur"] - work)
            pred = {n: (serial + sum(makespan(d, n) for _, d in groups(chunks))) / 1000.0 for n in threads}
            row = (p["dur"] / 1000.0, serial / 1000.0, len(chunks),
                   max((c["dur"] for c in chunks), default=0.0) / 1000.0, pred)
            per_pass.setdefault(p["name"], []).append(row)
            for name, d in groups(chunks):
                per_loop.setdefault((p["name"], name), []).append(
                    (sum(d) / 1000.0, len(d), max(d) / 1000.0, {n: makespan(d, n) / 1000.0 for n in threads}))
            total1 += p["dur"] / 1000.0
            for n in threads:
                totalN[n] += pred[n]
        frame_rows.append((total1, totalN))

    def med(xs):
        return statistics.median(xs)

    head = f"{'pass':32} {'1 thread':>9} {'serial':>8} {'chunks':>7} {'longest':>8}" + "".join(
        f" {str(n) + ' thr':>9}" for n in threads) + "".join(f" {'x' + str(n):>6}" for n in threads)
    print(f"{len(frames)} frames; ms, medians over frames; x<N>: 1-thread time / predicted time at N threads")
    print(head)
    for name, rows in sorted(per_pass.items(), key=lambda kv: -med([r[0] for r in kv[1]])):
        ms1 = med([r[0] for r in rows])
        if ms1 < 0.05:
            continue
        predN = {n: med([r[4][n] for r in rows]) for n in threads}
        line = f"{name[:32]:32} {ms1:9.2f} {med([r[1] for r in rows]):8.2f} {int(med([r[2] for r in rows])):7d} " \
               f"{med([r[3] for r in rows]):8.2f}"
        line += "".join(f" {predN[n]:9.2f}" for n in threads)
        line += "".join(f" {ms1 / predN[n]:6.1f}" for n in threads if predN[n] > 0)
        print(line)
    if a.detail:
        print()
        print(f"{'pass / parallel_for':44} {'1 thread':>9} {'chunks':>7} {'longest':>8}" +
              "".join(f" {str(n) + ' thr':>9}" for n in threads))
        for (pname, lname), rows in sorted(per_loop.items(), key=lambda kv: -med([r[0] for r in kv[1]])):
            ms1 = med([r[0] for r in rows])
            if ms1 < 0.05:
                continue
            print(f"{(pname + ' / ' + lname)[:44]:44} {ms1:9.2f} {int(med([r[1] for r in rows])):7d} "
                  f"{med([r[2] for r in rows]):8.2f}" + "".join(f" {med([r[3][n] for r in rows]):9.2f}" for n in threads))
        print()
    t1 = med([r[0] for r in frame_rows])
    tN = {n: med([r[1][n] for r in frame_rows]) for n in threads}
    print(f"{'passes in sequence':32} {t1:9.2f} {'':8} {'':7} {'':8}" + "".join(f" {tN[n]:9.2f}" for n in threads)
          + "".join(f" {t1 / tN[n]:6.1f}" for n in threads))


if __name__ == "__main__":
    main()
