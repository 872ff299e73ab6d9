#!/usr/bin/env python3
"""Docs are tests: run every shell block of README.md and docs/*.md as a user would type it.

Usage: scripts/docs_blocks.py --build-dir BUILD [--repo ROOT] [--only FILE[:LINE]] [--list] [-v]

What is a block: a fenced block opened with ```sh, ```bash or ```shell (plain ``` blocks are
output, file formats or diagrams and are not run). A block is runnable unless the line right
before its fence (blank lines skipped) is a marker:

  <!-- docs-test: skip (REASON) -->   not run; REASON is one of docker, root/systemd,
                                       postgres, data set, long benchmark, illustrative, ...
                                       (free text; the summary counts blocks per reason)
  <!-- docs-test: demo-server -->      run against a demo server of its own: the harness starts
                                       `locus-server --demo` on a free port with a database in
                                       the block's directory and rewrites localhost:8080 and
                                       127.0.0.1:8080 in the block to it, so the docs keep what
                                       a user types next to the server of ./scripts/run.sh.

A skip marker without a reason, or an unknown docs-test marker, fails the block.

--no-benchmarks (a build configured with -DLOCUS_BENCHMARKS=OFF, as the sanitized one is): a
block that runs a Google Benchmark program (build/bin/*_bench) is counted as marked, with the
reason "benchmarks not built", instead of failing for want of the program.

A page that is one walk-through (docs/your-building.md) says `<!-- docs-test: session -->` on a
line of its own: its runnable blocks then run in order as one script, in one directory, so a
later block uses what an earlier one set (it is reported as one block, at its first fence).

How a block runs: bash with `set -euo pipefail` (any failing command fails the block; curl
answering an HTTP error counts as failing: --fail-with-body is added unless it has -f), a time
limit (--timeout, 60 s), a clean environment (HOME, LANG=C.UTF-8, TMPDIR, LOCUS_REPO=the
repository root) whose PATH starts with BUILD/bin, so `locus` and `locus-server` resolve as
they do after `cmake --install` (which puts them in /usr/local/bin). The working directory is a
fresh temporary directory that mirrors the repository root: each top-level entry of the
repository is a symlink to it and `build` is a symlink to BUILD, so `build/bin/locus`,
`docs/examples/...` and `scripts/...` resolve, and the files a block writes (walk.jsonl, ...)
land in the temporary directory. Whatever the block left running (a server in the
background) is killed with its process group when it ends.

Output checks: a comment line `# -> {...}` (continued by `#     ...` lines) after a command
lists keys the answer has; each `"key":` named there must appear in the block's stdout.

Prints one line per block run (a failing one with its output), then a summary per file: runnable blocks
(passed), marked blocks per reason. Exits 1 if any runnable block failed.
"""

import argparse
import collections
import glob
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

FENCE_OPEN = re.compile(r"^(\s*)```(\w*)\s*$")
FENCE_CLOSE = re.compile(r"^\s*```\s*$")
BENCH_PROGRAM = re.compile(r"\bbuild/bin/\w+_bench\b")
MARKER = re.compile(r"^\s*<!--\s*docs-test:\s*(skip|demo-server)\s*(?:\((.*)\))?\s*-->\s*$")
SESSION = re.compile(r"^\s*<!--\s*docs-test:\s*session\s*-->\s*$")
SHELLS = {"sh", "bash", "shell"}
# curl -s exits 0 on an HTTP error: in a block an error answer fails the block (unless the block
# already chose -f / --fail itself).
PREAMBLE = """set -euo pipefail
curl() { local a; for a in "$@"; do case $a in --fail*|-[!-]*f*) command curl "$@"; return;; esac; done
  command curl --fail-with-body "$@"; }
"""
DEMO_HOSTS = re.compile(r"\b(localhost|127\.0\.0\.1):8080\b")


class Block:
    def __init__(self, path, line, text, mode, reason):
        self.path, self.line, self.text, self.mode, self.reason = path, line, text, mode, reason


def blocks_of(path, rel):
    """Every shell block of one Markdown file with the marker before it."""
    lines = open(path, encoding="utf-8").read().split("\n")
    out = []
    i = 0
    while i < len(lines):
        m = FENCE_OPEN.match(lines[i])
        if not m:
            i += 1
            continue
        start, lang = i, m.group(2)
        i += 1
        body = []
        while i < len(lines) and not FENCE_CLOSE.match(lines[i]):
            body.append(lines[i])
            i += 1
        i += 1
        if lang not in SHELLS:
            continue
        mode, reason = "run", ""
        j = start - 1
        while j >= 0 and not lines[j].strip():
            j -= 1
        mk = MARKER.match(lines[j]) if j >= 0 else None
        if j >= 0 and SESSION.match(lines[j]):
            pass  # the page's session marker, not this block's
        elif mk:
            mode = mk.group(1)
            reason = (mk.group(2) or "").strip()
            if mode == "skip" and not reason:
                mode, reason = "bad", "a skip marker needs a reason: <!-- docs-test: skip (REASON) -->"
        elif j >= 0 and "docs-test" in lines[j]:
            mode, reason = "bad", "unknown marker: " + lines[j].strip()
        out.append(Block(rel, start + 1, "\n".join(body) + "\n", mode, reason))
    if any(SESSION.match(l) for l in lines):
        runnable = [b for b in out if b.mode == "run"]
        if runnable:
            text = "".join("# --- %s:%d\n%s" % (rel, b.line, b.text) for b in runnable)
            out = [b for b in out if b.mode != "run"] + [Block(rel, runnable[0].line, text, "run", "")]
    return out


def expected_keys(text):
    """The "key": names of every `# -> ` comment (and its `#     ` continuation lines)."""
    keys = []
    inside = False
    for line in text.split("\n"):
        s = line.strip()
        if s.startswith("# -> "):
            inside = True
        elif not (inside and s.startswith("#     ")):
            inside = False
            continue
        keys += re.findall(r'"([A-Za-z_][A-Za-z0-9_]*)":', s)
    return sorted(set(keys))


def mirror(repo, build, into):
    for name in os.listdir(repo):
        if name in (".git", "build"):
            continue
        os.symlink(os.path.join(repo, name), os.path.join(into, name))
    os.symlink(build, os.path.join(into, "build"))


def start_demo(bin_dir, work, env):
    log = open(os.path.join(work, ".demo-server.log"), "w+")
    proc = subprocess.Popen(
        [os.path.join(bin_dir, "locus-server"), "--db", os.path.join(work, ".demo.db"), "--host", "127.0.0.1",
         "--port", "0", "--quiet", "--demo"],
        stdout=log, stderr=subprocess.STDOUT, env=env, cwd=work, start_new_session=True)
    deadline = time.time() + 15
    while time.time() < deadline:
        if proc.poll() is not None:
            break
        log.seek(0)
        for line in log.read().splitlines():
            try:
                ev = json.loads(line)
            except ValueError:
                continue
            if ev.get("event") == "listening":
                return proc, int(ev["port"])
        time.sleep(0.05)
    stop(proc)
    log.seek(0)
    raise RuntimeError("demo server did not start: " + log.read()[-500:])


def stop(proc):
    try:
        os.killpg(proc.pid, signal.SIGTERM)
    except ProcessLookupError:
        return
    try:
        proc.wait(5)
    except subprocess.TimeoutExpired:
        try:
            os.killpg(proc.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        proc.wait()


def run_block(block, repo, build, timeout, verbose):
    """(ok, seconds, message)"""
    bin_dir = os.path.join(build, "bin")
    work = tempfile.mkdtemp(prefix="docs-block-")
    t0 = time.time()
    demo = None
    try:
        mirror(repo, build, work)
        env = {
            "PATH": bin_dir + os.pathsep + "/usr/local/bin:/usr/bin:/bin",
            "HOME": work,
            "TMPDIR": work,
            "LANG": "C.UTF-8",
            "LOCUS_REPO": repo,
        }
        text = block.text
        if block.mode == "demo-server":
            demo, port = start_demo(bin_dir, work, env)
            text = DEMO_HOSTS.sub("127.0.0.1:%d" % port, text)
        script = os.path.join(work, ".block.sh")
        with open(script, "w") as f:
            f.write(PREAMBLE + text)
        out_path, err_path = os.path.join(work, ".stdout"), os.path.join(work, ".stderr")
        with open(out_path, "w") as out, open(err_path, "w") as err:
            proc = subprocess.Popen(["bash", "--noprofile", "--norc", script], stdout=out, stderr=err,
                                    stdin=subprocess.DEVNULL, env=env, cwd=work, start_new_session=True)
            try:
                rc = proc.wait(timeout)
            except subprocess.TimeoutExpired:
                rc = None
            stop(proc)  # and whatever it left in the background
        stdout = open(out_path, errors="replace").read()
        stderr = open(err_path, errors="replace").read()
        secs = time.time() - t0
        tail = "\n    ".join((stdout[-1500:] + "\n--- stderr ---\n" + stderr[-1500:]).split("\n"))
        if rc is None:
            return False, secs, "timed out after %d s\n    %s" % (timeout, tail)
        if rc != 0:
            return False, secs, "exit status %d\n    %s" % (rc, tail)
        missing = [k for k in expected_keys(block.text) if '"%s":' % k not in stdout]
        if missing:
            return False, secs, "output lacks keys shown in the docs: %s\n    %s" % (", ".join(missing), tail)
        return True, secs, (tail if verbose else "")
    except RuntimeError as e:
        return False, time.time() - t0, str(e)
    finally:
        if demo:
            stop(demo)
        shutil.rmtree(work, ignore_errors=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build-dir", required=True, help="the build directory (its bin/ holds locus, locus-server)")
    ap.add_argument("--repo", default=os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    ap.add_argument("--only", help="FILE or FILE:LINE (the fence's line)")
    ap.add_argument("--timeout", type=int, default=60, help="seconds per block")
    ap.add_argument("--list", action="store_true", help="list the blocks and their marks, run nothing")
    ap.add_argument("--no-benchmarks", action="store_true",
                    help="the build has no bench/ programs: blocks that run one are not run")
    ap.add_argument("-v", "--verbose", action="store_true")
    args = ap.parse_args()
    repo = os.path.abspath(args.repo)
    build = os.path.abspath(args.build_dir)
    for tool in ("locus", "locus-server"):
        if not os.access(os.path.join(build, "bin", tool), os.X_OK):
            sys.exit("docs_blocks: %s/bin/%s is missing: build it first" % (build, tool))

    files = ["README.md"] + sorted(os.path.relpath(p, repo) for p in glob.glob(os.path.join(repo, "docs", "*.md")))
    blocks = []
    for rel in files:
        blocks += blocks_of(os.path.join(repo, rel), rel)
    if args.only:
        f, _, line = args.only.partition(":")
        blocks = [b for b in blocks if b.path == f and (not line or b.line == int(line))]

    if args.no_benchmarks:
        for b in blocks:
            if b.mode == "run" and BENCH_PROGRAM.search(b.text):
                b.mode, b.reason = "skip", "benchmarks not built"

    if args.list:
        for b in blocks:
            print("%s:%d %s%s" % (b.path, b.line, b.mode, " (%s)" % b.reason if b.reason else ""))
        return 0

    t_all = time.time()
    stats = collections.OrderedDict((f, {"run": 0, "passed": 0, "marked": collections.Counter()}) for f in files)
    failed = 0
    for b in blocks:
        s = stats[b.path]
        if b.mode == "skip":
            s["marked"][b.reason] += 1
            continue
        s["run"] += 1
        if b.mode == "bad":
            ok, secs, msg = False, 0.0, b.reason
        else:
            ok, secs, msg = run_block(b, repo, build, args.timeout, args.verbose)
        status = "ok  " if ok else "FAIL"
        print("%s %s:%d (%.1f s)%s" % (status, b.path, b.line, secs, " demo-server" if b.mode == "demo-server" else ""),
              flush=True)
        if msg:
            print("    " + msg, flush=True)
        if ok:
            s["passed"] += 1
        else:
            failed += 1

    print("\ndocs blocks:")
    total_run = total_passed = total_marked = 0
    for f, s in stats.items():
        n_marked = sum(s["marked"].values())
        if not s["run"] and not n_marked:
            continue
        reasons = ", ".join("%d (%s)" % (n, r) for r, n in sorted(s["marked"].items()))
        print("  %-22s runnable %2d (passed %2d), marked %2d%s" % (f, s["run"], s["passed"], n_marked,
                                                                   ": " + reasons if reasons else ""))
        total_run += s["run"]
        total_passed += s["passed"]
        total_marked += n_marked
    print("  total: runnable %d (passed %d), marked %d, %.1f s" % (total_run, total_passed, total_marked,
                                                                  time.time() - t_all))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
