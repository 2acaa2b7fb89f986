#!/usr/bin/env python3
"""Run a cierva plan's shards on Dask distributed (docs/scaling.md).

    cierva uncertainty CASES --samples 256 --plan study/
    python3 run_dask.py study/ --shards 64                 # a LocalCluster on this machine
    python3 run_dask.py study/ --shards 64 --scheduler tcp://host:8786   # an existing cluster
    cierva uncertainty --from-plan study/

Each task is one `cierva evaluate DIR --shard I/N` on a worker: cierva stays one binary with no
engine in it, and the engine only schedules commands. A shard writes its results into the plan's
folder (which every worker must see: a shared file system), each evaluation as it finishes, so a
task that a lost worker had started takes up, on the worker Dask gives it next, where it
stopped. On a Slurm or PBS cluster, make the cluster with dask-jobqueue instead of LocalCluster
(docs/scaling.md has the lines).
"""
import argparse
import ctypes
import json
import os
import shutil
import signal
import subprocess
import sys
import threading
import time
import uuid

def die_with_parent():
    """What the shard's cierva runs before it starts (between fork and exec): end it when the
    worker that started it dies (Linux), so a killed worker leaves no shard running beside the
    one Dask starts again. libc is loaded here, in the worker, before the fork: loading a
    library between fork and exec is not safe in a threaded process."""
    try:
        libc = ctypes.CDLL("libc.so.6", use_errno=True)
    except OSError:
        return None
    return lambda: libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG


def evaluate_shard(cierva, plan, shard, shards, threads):
    """One shard, run as a command on the worker; its report (cierva's JSON)."""
    command = [cierva, "--quiet", "evaluate", plan, "--shard", f"{shard}/{shards}",
               "--threads", str(threads), "--format", "json"]
    done = subprocess.run(command, capture_output=True, text=True, preexec_fn=die_with_parent())
    if done.returncode != 0:
        raise RuntimeError(f"shard {shard}/{shards}: exit {done.returncode}: {done.stderr.strip()}")
    return json.loads(done.stdout)


def kill_one_worker_after(client, seconds):
    """For the resume measurement: SIGKILL one worker's process after `seconds` (its nanny
    starts a new one; Dask gives its task to a worker again)."""
    def kill():
        time.sleep(seconds)
        pids = client.run(os.getpid)
        address, pid = sorted(pids.items())[0]
        print(f"killing worker {address} (pid {pid}) at {seconds:.0f} s", flush=True)
        os.kill(pid, signal.SIGKILL)
    threading.Thread(target=kill, daemon=True).start()


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("plan", help="the plan's folder (cierva uncertainty --plan DIR)")
    ap.add_argument("--shards", type=int, required=True,
                    help="how many shards to cut the plan into (several a worker balances the load)")
    ap.add_argument("--workers", type=int, default=2, help="LocalCluster workers (default 2)")
    ap.add_argument("--threads", type=int, default=1,
                    help="evaluations a shard runs at once (default 1: one a worker)")
    ap.add_argument("--scheduler", help="an existing cluster's scheduler address instead of a LocalCluster")
    ap.add_argument("--cierva", default=shutil.which("cierva") or "cierva",
                    help="the cierva binary, as the workers find it (default: the one on this PATH)")
    ap.add_argument("--retries", type=int, default=0,
                    help="times a shard whose command failed is run again (default 0: a failure is "
                         "bad input or the model's, and named at the end; a shard whose worker is "
                         "lost is started again by Dask itself, distributed.scheduler.allowed-failures)")
    ap.add_argument("--kill-one-worker-after", type=float, metavar="S",
                    help="(measurement, LocalCluster only) SIGKILL one worker after S seconds")
    a = ap.parse_args()
    from dask.distributed import Client, LocalCluster, as_completed

    plan = os.path.abspath(a.plan)
    started = time.monotonic()
    if a.scheduler:
        client = Client(a.scheduler)
    else:
        # A task only starts `cierva evaluate` and waits for it, so on one machine a worker
        # needs no process of its own: thread workers start in hundredths of a second where
        # worker processes take about 0.4 s (docs/scaling.md). The kill measurement kills a
        # worker's process, so it has them.
        cluster = LocalCluster(n_workers=a.workers, threads_per_worker=1,
                               processes=a.kill_one_worker_after is not None,
                               dashboard_address=":0")
        client = Client(cluster)
    print(f"workers up in {time.monotonic() - started:.1f} s", flush=True)
    if a.kill_one_worker_after is not None and a.scheduler:
        ap.error("--kill-one-worker-after kills a local worker: give no --scheduler")
    if a.kill_one_worker_after is not None:
        kill_one_worker_after(client, a.kill_one_worker_after)
    # Keys of this run's own: another plan's shards on a shared scheduler are other tasks.
    run = uuid.uuid4().hex[:8]
    futures = [client.submit(evaluate_shard, a.cierva, plan, i, a.shards, a.threads,
                             key=f"cierva-{run}-shard-{i}-of-{a.shards}", pure=False, retries=a.retries)
               for i in range(1, a.shards + 1)]
    failed = []
    # Only `as_completed` holds the futures: each is released once read, so that a worker lost
    # later does not make Dask run its finished shards again.
    pending = as_completed(futures)
    del futures
    for future in pending:
        try:
            r = future.result()
            print(f"shard {r['shard']}/{r['of']}: {r['evaluations']} evaluations "
                  f"({r['already_done']} done before) in {r['seconds']:.1f} s", flush=True)
        except Exception as e:  # a shard that failed: named, and the others still run
            failed.append(str(e))
            print(f"failed: {e}", file=sys.stderr, flush=True)
        future.release()
    client.close()
    print(f"all shards in {time.monotonic() - started:.1f} s", flush=True)
    if failed:
        print(f"{len(failed)} shards failed: `cierva uncertainty --from-plan {plan}` names what is missing",
              file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
