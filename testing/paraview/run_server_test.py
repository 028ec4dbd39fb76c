#!/usr/bin/env python3
"""Runs a client script against its own pvserver on the loopback interface, then stops the server.

    run_server_test.py [--mpi N] [--timeout S] -- CLIENT_COMMAND...   ("{port}" in the command is replaced)

ParaView 5.11's pvserver has no option to choose the address it listens on: it listens on all interfaces.
So, when the kernel allows it (root or user namespaces), the server and the client run in a private network
namespace whose only interface is loopback (unshare -n); otherwise they run normally on a free port picked
on 127.0.0.1 and the server lives only for the test (it is started under `timeout` and killed at the end).
The X display (a Unix socket) is shared either way.
"""
import argparse
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import threading
import time

MPIRUN = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--mca", "btl", "self,vader",
          "-x", "DISPLAY", "-x", "PYTHONPATH"]


def in_private_netns():
    """Re-executes this script in a new network namespace with loopback up; returns True when running there."""
    if os.environ.get("WHITTED_NETNS") == "1":
        return True
    unshare, ip = shutil.which("unshare"), shutil.which("ip")
    if not unshare or not ip:
        return False
    probe = subprocess.run([unshare, "-n", ip, "link", "set", "lo", "up"], stdout=subprocess.DEVNULL,
                           stderr=subprocess.DEVNULL)
    if probe.returncode != 0:
        return False
    env = dict(os.environ, WHITTED_NETNS="1")
    cmd = [unshare, "-n", "sh", "-c", '"$0" link set lo up && exec "$@"', ip, sys.executable] + sys.argv
    sys.exit(subprocess.call(cmd, env=env))


def free_port():
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--pvserver", default="pvserver")
    ap.add_argument("--mpi", type=int, default=0, help="run pvserver under mpirun with N ranks")
    ap.add_argument("--timeout", type=int, default=240)
    ap.add_argument("client", nargs=argparse.REMAINDER)
    args = ap.parse_args()
    client = [a for a in args.client if a != "--"]
    if not client:
        ap.error("no client command")

    isolated = in_private_netns()
    port = free_port()
    server = ["timeout", "-s", "KILL", str(args.timeout), ]
    if args.mpi:
        server += MPIRUN + ["-np", str(args.mpi)]
    server += [args.pvserver, "--server-port=%d" % port, "--timeout=%d" % max(1, args.timeout // 60)]
    print("network: %s; server: %s" % ("private namespace (loopback only)" if isolated else "host, free port",
                                       " ".join(server)), flush=True)
    proc = subprocess.Popen(server, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            start_new_session=True)

    ready = threading.Event()

    def pump():
        for line in proc.stdout:
            sys.stdout.write("[pvserver] " + line)
            sys.stdout.flush()
            if re.search(r"Accepting connection", line):
                ready.set()
        ready.set()

    threading.Thread(target=pump, daemon=True).start()
    status = 1
    try:
        if not ready.wait(60) or proc.poll() is not None:
            print("FAILED: pvserver did not start")
            return 1
        cmd = [a.replace("{port}", str(port)) for a in client]
        print("client: " + " ".join(cmd), flush=True)
        status = subprocess.call(cmd, timeout=args.timeout)
    finally:
        # pvserver exits when its client disconnects; give it a moment, then stop the whole group.
        try:
            proc.wait(timeout=15)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
    return status


if __name__ == "__main__":
    sys.exit(main())
