#!/usr/bin/env python3
"""A farm's start on a cold program cache: what N ranks pay to compile
(docs/scale-out.md, *How the speedup scales with N nodes*).

usage: cold_farm.py [--build DIR] [--vs DIR] [--ranks 2] [--rounds 2]
                    [--model FILE] [--size WxH] [--bucket WxH] [--device intel]

Each round renders the same image four ways, each with new, empty
PERMA_CACHE_DIR and POCL_CACHE_DIR directories (a node that never ran the
program), and prints wall and CPU seconds (user + system of every process):

  cold, 1 process      reyes-render alone: one compile
  cold, N ranks        mpirun -n N reyes-render: the ranks build at once
  warm, N ranks        the same again on the caches the last run filled
  mpirun start-up      mpirun -n N true

With --vs DIR the N-rank cold render of a second build (e.g. one without
the shared build lock) runs in each round too, after this one's.  The
ranks share one node here, so they share PoCL's kernel cache as ranks
on a shared cache directory would; CPU seconds say how many compiles
there were, whatever the machine's load does to the wall time.
--device intel runs on Intel's OpenCL CPU runtime (the intel suite's ICD
directory in the build), which compiles in clBuildProgram and whose
programs perma's cache stores.
"""
import argparse
import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time


def children_cpu():
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def timed(command, env):
    cpu, start = children_cpu(), time.monotonic()
    result = subprocess.run(command, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall, cpu = time.monotonic() - start, children_cpu() - cpu
    if result.returncode != 0:
        sys.exit("cold_farm.py: %s failed (status %d):\n%s" % (" ".join(command), result.returncode,
                                                               result.stdout[-3000:]))
    return wall, cpu


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--build", default="build")
    parser.add_argument("--vs")
    parser.add_argument("--ranks", type=int, default=2)
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--model", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                                        "shared", "models", "teapot.bpt"))
    parser.add_argument("--size", default="256x256")
    parser.add_argument("--bucket", default="64x64")
    parser.add_argument("--device", choices=["pocl", "intel"], default="pocl")
    args = parser.parse_args()
    mpirun = shutil.which("mpirun")
    if not mpirun:
        sys.exit("cold_farm.py: mpirun is not installed")
    scratch = tempfile.mkdtemp(prefix="perma-cold-farm.")
    env = dict(os.environ)
    if args.device == "intel":
        env["OCL_ICD_VENDORS"] = os.path.join(os.path.abspath(args.build), "tests", "portability", "icd")
        env["PERMA_DEVICE"] = "intel"
    launch = [mpirun, "--oversubscribe", "--allow-run-as-root", "--bind-to", "none", "--mca", "btl", "self,vader",
              "--mca", "oob_tcp_if_include", "lo", "-x", "PERMA_CACHE_DIR", "-x", "POCL_CACHE_DIR"]
    for name in ("OCL_ICD_VENDORS", "PERMA_DEVICE"):
        if name in env:
            launch += ["-x", name]
    launch += ["-n", str(args.ranks)]

    def render(build, ranks):
        command = [os.path.join(build, "examples", "reyes", "reyes-render"), args.model, "--size", args.size,
                   "--bucket", args.bucket, "-o", os.path.join(scratch, "out.png")]
        return launch + command if ranks else command

    def fresh_caches(tag):
        for name in ("PERMA_CACHE_DIR", "POCL_CACHE_DIR"):
            env[name] = tempfile.mkdtemp(prefix=tag + "-" + name.split("_")[0].lower() + ".", dir=scratch)

    rows = {}
    try:
        for r in range(args.rounds):
            measures = []
            fresh_caches("one%d" % r)
            measures.append(("cold, 1 process", timed(render(args.build, 0), env)))
            fresh_caches("farm%d" % r)
            measures.append(("cold, %d ranks" % args.ranks, timed(render(args.build, args.ranks), env)))
            measures.append(("warm, %d ranks" % args.ranks, timed(render(args.build, args.ranks), env)))
            if args.vs:
                fresh_caches("vs%d" % r)
                measures.append(("cold, %d ranks, %s" % (args.ranks, args.vs), timed(render(args.vs, args.ranks), env)))
            measures.append(("mpirun start-up", timed(launch + ["true"], env)))
            for name, (wall, cpu) in measures:
                rows.setdefault(name, []).append((wall, cpu))
                print("round %d: %-40s wall %7.2f s  CPU %7.2f s" % (r + 1, name, wall, cpu), flush=True)
    finally:
        shutil.rmtree(scratch, ignore_errors=True)
    print("\nload average at the end: %s (%s, %s)" % (" ".join("%.1f" % x for x in os.getloadavg()), args.device,
                                                     args.model))
    print("%-44s %-22s %s" % ("", "wall s (each round)", "CPU s (each round)"))
    for name, values in rows.items():
        print("%-44s %-22s %s" % (name, " ".join("%.2f" % w for w, _ in values), " ".join("%.2f" % c for _, c in values)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
