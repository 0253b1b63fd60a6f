#!/usr/bin/env python3
"""
A lossy, delaying point-to-point link for the kernel's own TCP, inside a network namespace the
loss harness made (there is no netem qdisc on these machines: docs/webrtc.md).

It opens a TUN device, gives it the addresses LOCAL peer PEER, and loops: every IPv4 packet the
kernel routes to PEER is dropped with probability `loss` or held for `latency ± jitter` ms (order
kept per direction) and then written back with source and destination swapped. A client that
connects to PEER:port so reaches a server bound to LOCAL:port (or 0.0.0.0:port) through the
"link", and TCP's SACK, fast retransmit, RTO and tail-loss probes are the kernel's.

Python because opening a TUN device takes an ioctl, which Node cannot make without a native addon.

Commands on stdin, one a line: `set LATENCY JITTER LOSS` (the conditions from now on, each
direction), `stats` (prints one JSON line: packets, bytes and drops each way; bytes are TCP
segments with their TCP headers, without the IP header), `quit`. Prints `ready` once the device is up.
"""
import argparse
import fcntl
import heapq
import json
import os
import random
import select
import struct
import subprocess
import sys
import time

TUNSETIFF = 0x400454CA
IFF_TUN = 0x0001
IFF_NO_PI = 0x1000


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--name", default="fsnet0")
    ap.add_argument("--local", default="10.77.0.1")
    ap.add_argument("--peer", default="10.77.0.2")
    ap.add_argument("--server-port", type=int, required=True)
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()

    fd = os.open("/dev/net/tun", os.O_RDWR | os.O_NONBLOCK)
    fcntl.ioctl(fd, TUNSETIFF, struct.pack("16sH", args.name.encode(), IFF_TUN | IFF_NO_PI))
    subprocess.run(["ip", "addr", "add", args.local, "peer", args.peer, "dev", args.name], check=True)
    subprocess.run(["ip", "link", "set", args.name, "up"], check=True)

    rng = random.Random(args.seed)
    cond = {"latency": 0.0, "jitter": 0.0, "loss": 0.0}
    stats = {d: {"packets": 0, "bytes": 0, "lost": 0} for d in ("up", "down")}
    # Per direction, the release time of the last packet (order is kept), and one heap of all.
    last = {"up": 0.0, "down": 0.0}
    queue: list[tuple[float, int, bytes]] = []
    seq = 0
    stdin = sys.stdin.fileno()
    pending = b""
    print("ready", flush=True)

    while True:
        now = time.monotonic()
        while queue and queue[0][0] <= now:
            _, _, pkt = heapq.heappop(queue)
            try:
                os.write(fd, pkt)
            except OSError:
                pass
        timeout = max(0.0, queue[0][0] - now) if queue else 0.5
        readable, _, _ = select.select([fd, stdin], [], [], timeout)
        if stdin in readable:
            # Unbuffered: several commands may come in one read (a buffered readline would keep
            # the second where select() cannot see it).
            chunk = os.read(stdin, 4096)
            if not chunk:
                break
            pending += chunk
            quit_now = False
            while b"\n" in pending:
                line, pending = pending.split(b"\n", 1)
                words = line.decode().split()
                if not words:
                    continue
                if words[0] == "quit":
                    quit_now = True
                elif words[0] == "set":
                    cond = {"latency": float(words[1]), "jitter": float(words[2]), "loss": float(words[3])}
                elif words[0] == "stats":
                    print(json.dumps(stats), flush=True)
            if quit_now:
                break
        if fd not in readable:
            continue
        while True:
            try:
                pkt = os.read(fd, 65535)
            except BlockingIOError:
                break
            if len(pkt) < 20 or pkt[0] >> 4 != 4:
                continue
            ihl = (pkt[0] & 0x0F) * 4
            src_port = struct.unpack("!H", pkt[ihl : ihl + 2])[0] if pkt[9] == 6 else 0
            direction = "down" if src_port == args.server_port else "up"
            s = stats[direction]
            s["packets"] += 1
            s["bytes"] += len(pkt) - ihl
            if cond["loss"] > 0 and rng.random() < cond["loss"]:
                s["lost"] += 1
                continue
            delay = cond["latency"] + (rng.random() * 2 - 1) * cond["jitter"]
            at = max(time.monotonic() + delay / 1000, last[direction])
            last[direction] = at
            swapped = pkt[:12] + pkt[16:20] + pkt[12:16] + pkt[20:]
            seq += 1
            heapq.heappush(queue, (at, seq, swapped))
    os.close(fd)


if __name__ == "__main__":
    main()
