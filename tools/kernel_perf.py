#!/usr/bin/env python3
"""Where each kernel's time goes on lavapipe: perf samples attributed to kernels.

    tools/kernel_perf.py [--warmup S] [--seconds S] [--top N] [--kernel K] -- \\
        path/to/wavetrace render SCENE [ARGS...]

Runs the render with `--profile` and WAVETRACE_KERNEL_TRACE (gpu::command::
KERNEL_TRACE_VAR: each dispatch's start and end in lavapipe's timestamp clock, which
is CLOCK_MONOTONIC), records its threads with `perf record -k CLOCK_MONOTONIC` for
--seconds after --warmup seconds (give it a render longer than both), and gives each
sample to the kernel whose dispatch was running at its time. llvmpipe's JIT code has
no symbols, so the hot code is read from the live process with gdb before it is
stopped. Prints, per kernel, its share of the samples, the share of its samples on
the instructions after gathers, scatters, divisions and square roots, and locked
atomics (a sample lands on the instruction after a slow one), and its hottest
instructions. Needs perf and gdb (Debian: linux-perf, gdb); on a machine without
hardware counters perf samples by the CPU clock, which is enough.

docs/performance.md ("Kernels attributed by timestamps") says what it found.
"""
import argparse
import bisect
import collections
import os
import re
import signal
import subprocess
import sys
import tempfile
import time


def classify(ins):
    op = ins.split()[0] if ins.split() else "?"
    if "gather" in op:
        return "gather"
    if "scatter" in op:
        return "scatter"
    if op.startswith(("vdiv", "vsqrt", "div", "sqrt")):
        return "div/sqrt"
    if op == "lock" or op.startswith(("xchg", "cmpxchg")):
        return "atomic"
    return "other"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--warmup", type=float, default=6.0, help="seconds before recording")
    ap.add_argument("--seconds", type=float, default=8.0, help="seconds recorded")
    ap.add_argument("--top", type=int, default=10, help="hottest instructions per kernel")
    ap.add_argument("--kernel", action="append", help="only these kernels (repeatable)")
    ap.add_argument("command", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    cmd = a.command[1:] if a.command[:1] == ["--"] else a.command
    if not cmd:
        ap.error("give the render command after --")
    if "--profile" not in cmd:
        cmd = cmd + ["--profile"]
    tmp = tempfile.mkdtemp(prefix="kernel_perf.")
    trace = os.path.join(tmp, "kernels.txt")
    data = os.path.join(tmp, "perf.data")
    env = dict(os.environ, WAVETRACE_KERNEL_TRACE=trace)
    render = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        time.sleep(a.warmup)
        if render.poll() is not None:
            sys.exit("the render ended within --warmup: give it more samples")
        subprocess.run(["perf", "record", "-q", "-k", "CLOCK_MONOTONIC", "-F", "4000", "-p",
                        str(render.pid), "-o", data, "--", "sleep", str(a.seconds)],
                       check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if render.poll() is not None:
            sys.exit("the render ended while perf recorded: give it more samples")
        samples = subprocess.run(["perf", "script", "-i", data, "-F", "time,ip"], check=True,
                                 capture_output=True, text=True).stdout.splitlines()
        spans = []
        with open(trace) as f:
            for line in f:
                label, start, end = line.split()
                spans.append((int(start), int(end), label))
        spans.sort()
        starts = [s[0] for s in spans]
        per_kernel = collections.defaultdict(collections.Counter)
        for line in samples:
            f = line.split()
            if len(f) < 2:
                continue
            t = int(round(float(f[0].rstrip(":")) * 1e9))
            ip = int(f[1], 16)
            i = bisect.bisect_right(starts, t) - 1
            label = spans[i][2] if i >= 0 and spans[i][0] <= t < spans[i][1] else "(between)"
            per_kernel[label][ip] += 1
        # The JIT code: user-space addresses outside the mapped files.
        maps = []
        with open(f"/proc/{render.pid}/maps") as f:
            for line in f:
                r, _, _, _, _, *name = line.split()
                lo, hi = (int(x, 16) for x in r.split("-"))
                maps.append((lo, hi, name[0] if name else ""))

        def jit(ip):
            return any(lo <= ip < hi and not n.startswith("/") for lo, hi, n in maps) \
                and ip < 0x800000000000
        hot_pages = collections.Counter()
        for c in per_kernel.values():
            for ip, n in c.items():
                if jit(ip):
                    hot_pages[ip >> 10] += n
        pages = [p for p, n in hot_pages.items() if n >= 10]
        gdb = ["gdb", "-p", str(render.pid), "-batch"]
        for p in pages:
            gdb += ["-ex", f"x/400i {p << 10:#x}"]
        dis_text = subprocess.run(gdb, capture_output=True, text=True, timeout=300).stdout
    finally:
        render.send_signal(signal.SIGKILL)
        render.wait()
    dis = {}
    for line in dis_text.splitlines():
        m = re.match(r"\s*(0x[0-9a-f]+)(?: <[^>]*>)?:\s*(.*)", line)
        if m:
            dis.setdefault(int(m.group(1), 16), m.group(2))
    order = sorted(dis)
    index = {x: i for i, x in enumerate(order)}
    total = sum(sum(c.values()) for c in per_kernel.values())
    print(f"{total} samples over {a.seconds:.0f} s; {cmd[0]} {' '.join(cmd[1:])}")
    for label, c in sorted(per_kernel.items(), key=lambda kv: -sum(kv[1].values())):
        if a.kernel and label not in a.kernel:
            continue
        n = sum(c.values())
        # A sample lands on the instruction after the one that took the time.
        charged = collections.Counter()
        outside = 0
        for ip, k in c.items():
            i = index.get(ip)
            if i is None:
                outside += k
            else:
                charged[order[i - 1] if i > 0 else ip] += k
        classes = collections.Counter()
        for ip, k in charged.items():
            classes[classify(dis[ip])] += k
        share = ", ".join(f"{cl} {100 * k / n:.0f}%" for cl, k in classes.most_common())
        print(f"\n{label}: {100 * n / total:.1f}% of the samples ({n}); "
              f"outside the JIT code {100 * outside / n:.0f}%; {share}")
        for ip, k in charged.most_common(a.top):
            print(f"  {100 * k / n:5.1f}%  {ip:#x}  {dis[ip][:80]}")


if __name__ == "__main__":
    main()
