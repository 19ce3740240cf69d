#!/usr/bin/env python3
"""Mutation check of the GPU physics: do the tests see a small error in the GLSL?

Applies, one at a time, the mutations listed in tools/mutations.txt (each an exact,
unique piece of a shader and what replaces it), rebuilds, runs the tests the entry names,
and reports whether the tests *killed* the mutant (some test failed), whether it
*survived* (every named test passed: a hole in the suite), or was *stillborn* (the
mutated shader did not compile: a bad entry, not a test result).

The mutants are built in a scratch git worktree of HEAD with its own target dir (the
working tree and its builds are never touched), at the lowest CPU priority.

    tools/mutate.py                      # every mutation
    tools/mutate.py diffuse-cosine ...   # only these ids
    tools/mutate.py --list               # the ids
Options: --worktree DIR (default $TMPDIR/wavetrace-mutants), --target DIR (default
DIR/target; seed it with a copy of a warm target dir to save the first build),
--report FILE (markdown, default stdout only), --skip-baseline (the unmutated run of
the named tests, when the whole suite just passed on HEAD).

Format of tools/mutations.txt: blocks separated by blank lines, each
    id: <name>
    file: <path under the repository>
    find: <text, exactly once in the file>
    replace: <text>
    tests: <test file>[::<filter>] [<test file>[::<filter>] ...]
    why: <what the mutation breaks>
Lines starting with '#' are comments. `\\n` in find/replace stands for a newline.
"""

import argparse
import os
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
LIST = os.path.join(ROOT, "tools", "mutations.txt")


def parse(path):
    """The mutations of `path`, as dicts, in file order; exits on a malformed block."""
    muts, cur = [], {}
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines() + [""]
    for n, line in enumerate(lines, 1):
        if line.startswith("#"):
            continue
        if not line.strip():
            if cur:
                missing = {"id", "file", "find", "replace", "tests", "why"} - cur.keys()
                if missing:
                    sys.exit(f"{path}:{n}: mutation {cur.get('id', '?')} lacks {sorted(missing)}")
                muts.append(cur)
                cur = {}
            continue
        key, sep, value = line.partition(": ")
        if not sep:
            key, value = line.rstrip(":"), ""
        if key not in ("id", "file", "find", "replace", "tests", "why"):
            sys.exit(f"{path}:{n}: unknown key {key!r}")
        cur[key] = value.replace("\\n", "\n")
    ids = [m["id"] for m in muts]
    dup = {i for i in ids if ids.count(i) > 1}
    if dup:
        sys.exit(f"{path}: duplicate ids {sorted(dup)}")
    return muts


def run(cmd, cwd, env, log):
    """Runs `cmd` at the lowest priority, appending its output to `log`; its exit code."""
    with open(log, "a", encoding="utf-8") as out:
        out.write(f"\n$ {' '.join(cmd)}\n")
        out.flush()
        return subprocess.call(["nice", "-n", "19"] + cmd, cwd=cwd, env=env, stdout=out, stderr=subprocess.STDOUT)


def test_commands(spec):
    """`cargo test` command lines for a `tests:` field."""
    cmds = []
    for item in spec.split():
        binary, _, name_filter = item.partition("::")
        cmd = ["cargo", "test", "--test", binary]
        if name_filter:
            cmd += ["--", name_filter]
        cmds.append(cmd)
    return cmds


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("ids", nargs="*")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--worktree", default=os.path.join(tempfile.gettempdir(), "wavetrace-mutants"))
    ap.add_argument("--target")
    ap.add_argument("--report")
    ap.add_argument("--skip-baseline", action="store_true",
                    help="do not first run the named tests unmutated (when the suite just passed on HEAD)")
    args = ap.parse_args()

    muts = parse(LIST)
    if args.list:
        for m in muts:
            print(f"{m['id']:32} {m['file']}: {m['why']}")
        return 0
    if args.ids:
        unknown = set(args.ids) - {m["id"] for m in muts}
        if unknown:
            sys.exit(f"unknown mutation ids: {sorted(unknown)}")
        muts = [m for m in muts if m["id"] in args.ids]

    wt = args.worktree
    head = subprocess.check_output(["git", "rev-parse", "HEAD"], cwd=ROOT, text=True).strip()
    if not os.path.isdir(wt):
        subprocess.check_call(["git", "worktree", "add", "--detach", wt, head], cwd=ROOT)
    else:
        # The repository's HEAD (not the scratch tree's own, which is older).
        subprocess.check_call(["git", "checkout", "--detach", "--force", head], cwd=wt)
    env = dict(os.environ, CARGO_TARGET_DIR=args.target or os.path.join(wt, "target"))
    log = os.path.join(wt, "mutate.log")

    # Every entry must apply to HEAD's shaders, exactly once.
    for m in muts:
        with open(os.path.join(wt, m["file"]), encoding="utf-8") as f:
            count = f.read().count(m["find"])
        if count != 1:
            sys.exit(f"mutation {m['id']}: its text occurs {count} times in {m['file']} (must be once)")

    # The unmutated tree must pass the tests the entries name, or a kill means nothing.
    baseline = sorted({" ".join(c) for m in muts for c in test_commands(m["tests"])})
    if not args.skip_baseline:
        print("baseline: building and running every named test on the unmutated tree", flush=True)
    for cmd in [] if args.skip_baseline else baseline:
        if run(cmd.split(), wt, env, log) != 0:
            sys.exit(f"baseline fails: {cmd} (see {log})")

    rows = []
    for m in muts:
        path = os.path.join(wt, m["file"])
        with open(path, encoding="utf-8") as f:
            original = f.read()
        t0 = time.time()
        try:
            with open(path, "w", encoding="utf-8") as f:
                f.write(original.replace(m["find"], m["replace"], 1))
            binaries = [a for item in m["tests"].split() for a in ("--test", item.partition("::")[0])]
            if run(["cargo", "test", "--no-run"] + binaries, wt, env, log) != 0:
                outcome, by = "stillborn", "build failed"
            else:
                outcome, by = "survived", ""
                for cmd in test_commands(m["tests"]):
                    if run(cmd, wt, env, log) != 0:
                        outcome, by = "killed", " ".join(cmd[3:])
                        break
        finally:
            with open(path, "w", encoding="utf-8") as f:
                f.write(original)
        rows.append((m, outcome, by, time.time() - t0))
        print(f"{m['id']:32} {outcome:9} {by}  ({time.time() - t0:.0f} s)", flush=True)

    lines = ["| mutation | file | what it breaks | outcome | killed by |", "|---|---|---|---|---|"]
    for m, outcome, by, _ in rows:
        lines.append(f"| {m['id']} | {m['file']} | {m['why']} | {outcome} | {by} |")
    killed = sum(1 for r in rows if r[1] == "killed")
    lines.append("")
    lines.append(f"{killed} of {len(rows)} killed; survived: "
                 + (", ".join(r[0]["id"] for r in rows if r[1] == "survived") or "none")
                 + "; stillborn: " + (", ".join(r[0]["id"] for r in rows if r[1] == "stillborn") or "none"))
    report = "\n".join(lines)
    print(report)
    if args.report:
        with open(args.report, "w", encoding="utf-8") as f:
            f.write(report + "\n")
    return 0 if all(r[1] == "killed" for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
