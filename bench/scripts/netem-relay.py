#!/usr/bin/env python3
"""A user-space netem between two TUN devices, for kernels without sch_netem (this build machine's has none, and
no modules to load: `tc qdisc add ... netem` answers "Specified qdisc kind is unknown").

Moves real IP packets between two network namespaces through two TUN devices and applies, per direction, a delay
with jitter, random loss and reordering, as `tc qdisc ... netem delay D J loss L reorder R` would. TCP on either side
is the kernel's own, so a loss means a real retransmission and a downed link (`ip -n NS link set DEV down`) means
real timeouts and unreachable routes.

usage: netem-relay.py DEV_A DEV_B [--delay-ms 2] [--jitter-ms 1] [--loss 0.01] [--reorder 0.05] [--seed N]
                      [--stats FILE]
The devices are created here (IFF_TUN | IFF_NO_PI, not persistent: they vanish with the relay) and left for the
caller to move into namespaces and address. The relay prints "ready" once both are open and runs until SIGTERM or
SIGINT; it then prints its counters (and writes them as one JSON line to --stats).

Differences from netem, on purpose: jitter is uniform in [delay - jitter, delay + jitter] (netem's default is also
uniform without a distribution table); a reordered packet is sent at once, overtaking the delayed ones (netem's
reorder); no rate limit, corruption or duplication.
"""
import argparse, fcntl, heapq, json, os, random, select, signal, struct, sys, time

TUNSETIFF = 0x400454CA
IFF_TUN, IFF_NO_PI = 0x0001, 0x1000
MAX_QUEUED = 100_000  # packets held for delay at once; beyond it new ones are dropped (counted), as a full qdisc would


def open_tun(name):
    fd = os.open("/dev/net/tun", os.O_RDWR | os.O_NONBLOCK)
    fcntl.ioctl(fd, TUNSETIFF, struct.pack("16sH", name.encode(), IFF_TUN | IFF_NO_PI))
    return fd


def main():
    p = argparse.ArgumentParser()
    p.add_argument("dev_a"); p.add_argument("dev_b")
    p.add_argument("--delay-ms", type=float, default=2.0)
    p.add_argument("--jitter-ms", type=float, default=1.0)
    p.add_argument("--loss", type=float, default=0.01)
    p.add_argument("--reorder", type=float, default=0.05)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--stats", default=None)
    a = p.parse_args()
    rnd = random.Random(a.seed)
    fa, fb = open_tun(a.dev_a), open_tun(a.dev_b)
    other = {fa: fb, fb: fa}
    stats = {"packets": 0, "lost": 0, "reordered": 0, "unwritable": 0, "overflow": 0}
    queue, seq = [], 0
    running = True

    def stop(*_):
        nonlocal running
        running = False

    signal.signal(signal.SIGTERM, stop)
    signal.signal(signal.SIGINT, stop)
    print("ready", flush=True)
    while running:
        now = time.monotonic()
        while queue and queue[0][0] <= now:
            _, _, fd, pkt = heapq.heappop(queue)
            try:
                os.write(fd, pkt)
            except OSError:
                stats["unwritable"] += 1  # that side's link is down (or its queue full): the packet is lost there
        timeout = max(0.0, queue[0][0] - now) if queue else 0.2
        try:
            ready, _, _ = select.select([fa, fb], [], [], timeout)
        except InterruptedError:
            continue
        for fd in ready:
            while True:
                try:
                    pkt = os.read(fd, 65535)
                except (BlockingIOError, OSError):
                    break
                stats["packets"] += 1
                if rnd.random() < a.loss:
                    stats["lost"] += 1
                    continue
                if len(queue) >= MAX_QUEUED:
                    stats["overflow"] += 1
                    continue
                if rnd.random() < a.reorder:
                    due = time.monotonic()
                    stats["reordered"] += 1
                else:
                    due = time.monotonic() + max(0.0, a.delay_ms + rnd.uniform(-a.jitter_ms, a.jitter_ms)) / 1000.0
                seq += 1
                heapq.heappush(queue, (due, seq, other[fd], pkt))
    print("relay: %(packets)d packets, %(lost)d lost, %(reordered)d reordered, %(unwritable)d dropped at a downed link, "
          "%(overflow)d dropped at a full queue" % stats, file=sys.stderr, flush=True)
    if a.stats:
        with open(a.stats, "w") as f:
            f.write(json.dumps(stats) + "\n")


if __name__ == "__main__":
    main()
