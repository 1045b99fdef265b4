"""Where the firmware bench's instructions go, per function (issue 17).

Runs a bench image (fw/bench_cortex_m.c or fw/bench_q_cortex_m.c) in QEMU with its translation and
execution log (`-d in_asm,exec,nochain`) streamed through a FIFO: each translated block's
instruction count comes from its `IN:` listing, and each `Trace` line adds that count to the block's
function. Inline helpers count in their caller; libgcc's division and multiplication helpers
(`__aeabi_ldivmod`, `__udivmoddi4`, `__aeabi_lmul`, ...) show by name. A segment starts at each
entry to `ss_actuator_init_q` / `ss_actuator_init_f32` (the bench initialises each model once),
so the LS and LuGre runs are reported apart; figures are instructions per actuator step
(the segment's total over the bench's 20 000 steps), the waveform player and its loop alone
included. Blocks that the instruction budget stops at their entry are counted too: the totals
come out 1-2 % above the bench's own count. The helpers' instructions are listed a second time by
their caller (the last function outside them that ran): which code's products or divisions they are.

    .venv/bin/python bench/fw_profile.py cortex-m3 q      (after bash bench/firmware_bench.sh)
    .venv/bin/python bench/fw_profile.py cortex-m4f f32
    .venv/bin/python bench/fw_profile.py cortex-m0plus q --lines ss_actuator_step_q  (by line)
"""

from __future__ import annotations

import argparse
import collections
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BOARDS = {"cortex-m4f": "mps2-an386", "cortex-m3": "mps2-an385", "cortex-m0plus": "mps2-an385"}
IMAGES = {"q": "stickslip_q_bench_fw.elf", "f32": "stickslip_bench_fw.elf"}
SEGMENT_START = ("ss_actuator_init_q", "ss_actuator_init_f32")  # their entry addresses start one
BENCH_STEPS = 20000  # fw/bench_*.c


def entries(image: Path, names: tuple[str, ...]) -> set[int]:
    """The entry addresses of the named functions (Thumb bit cleared), from the image's symbols."""
    out = subprocess.run(
        ["arm-none-eabi-nm", str(image)], capture_output=True, text=True, check=True
    )
    return {
        int(a, 16) & ~1
        for a, _, n in (ln.split() for ln in out.stdout.splitlines() if ln.count(" ") == 2)
        if n in names
    }


def profile(
    target: str, variant: str, lines_of: str = ""
) -> tuple[list[collections.Counter[str]], list[collections.Counter[int]]]:
    image = ROOT / "build" / target / "fw" / IMAGES[variant]
    if not image.exists():
        sys.exit(f"{image} not found: run bash bench/firmware_bench.sh first")
    starts = entries(image, SEGMENT_START)
    with tempfile.TemporaryDirectory() as tmp:
        fifo = Path(tmp) / "qemu.log"
        os.mkfifo(fifo)
        cmd = [
            "qemu-system-arm", "-M", BOARDS[target], "-nographic", "-monitor", "none",
            "-icount", "shift=0", "-semihosting-config", "enable=on,target=native",
            "-serial", "null", "-kernel", str(image),
            "-d", "in_asm,exec,nochain", "-D", str(fifo),
        ]  # fmt: skip
        proc = subprocess.Popen(cmd, stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
        # A block is listed when translated and traced at each execution. Under -icount QEMU
        # retranslates a block shorter where the instruction budget ends, at the same guest
        # address: so a block is known by its host address (the Trace line's pointer), bound to
        # the listing of its guest address that came just before its first execution.
        listed: dict[
            int, tuple[int, str, list[int]]
        ] = {}  # guest address -> (count, function, pcs)
        block: dict[str, tuple[int, str, list[int]]] = {}  # host address -> the same
        segments: list[collections.Counter[str]] = [collections.Counter()]
        # per segment, instructions executed at each address of the function lines_of names
        at_pc: list[collections.Counter[int]] = [collections.Counter()]
        block_pc, block_n, block_sym = -1, 0, ""
        block_pcs: list[int] = []
        caller = "?"  # the last function outside libgcc's helpers: who called the helper running
        with open(fifo, errors="replace") as log:
            for line in log:
                if line.startswith("0x") and block_sym:
                    pc_i = int(line.split(":", 1)[0], 16)
                    if block_pc < 0:
                        block_pc = pc_i
                    block_n += 1
                    if block_sym == lines_of:
                        block_pcs.append(pc_i)
                    continue
                if block_pc >= 0:  # any other line ends a listing
                    listed[block_pc] = (block_n, block_sym, block_pcs)
                    block_pc, block_sym, block_pcs = -1, "", []
                if line.startswith("Trace "):
                    host, rest = line.split(" ", 3)[2], line.split("[", 1)[1]
                    pc = int(rest.split("/", 2)[1], 16)
                    if pc in listed:
                        block[host] = listed.pop(pc)
                    if pc in starts:
                        segments.append(collections.Counter())
                        at_pc.append(collections.Counter())
                    n, sym, pcs = block.get(host, (0, "?", []))
                    segments[-1][sym] += n
                    at_pc[-1].update(pcs)
                    if sym.startswith("__"):
                        segments[-1][f"{sym} <- {caller}"] += n
                    else:
                        caller = sym
                elif line.startswith("IN:"):
                    block_pc, block_n, block_sym = -1, 0, line[3:].strip() or "?"
        proc.wait(timeout=60)
    return segments, at_pc


def source_lines(image: Path, counts: collections.Counter[int]) -> collections.Counter[str]:
    """Instruction counts by source line (file:line of each address; inlined code at its own)."""
    pcs = sorted(counts)
    if not pcs:
        return collections.Counter()
    out = subprocess.run(
        ["arm-none-eabi-addr2line", "-e", str(image), *(hex(a) for a in pcs)],
        capture_output=True, text=True, check=True,
    )  # fmt: skip
    by_line: collections.Counter[str] = collections.Counter()
    for a, where in zip(pcs, out.stdout.splitlines()):
        by_line[where.rsplit("/", 1)[-1]] += counts[a]
    return by_line


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("target", choices=sorted(BOARDS))
    ap.add_argument("variant", choices=sorted(IMAGES))
    ap.add_argument("--top", type=int, default=14, help="functions listed per model")
    ap.add_argument("--lines", default="", metavar="FUNCTION", help="also its source lines' counts")
    a = ap.parse_args()
    segments, at_pc = profile(a.target, a.variant, a.lines)
    segments, at_pc = segments[1:], at_pc[1:]  # before the first init: start-up
    image = ROOT / "build" / a.target / "fw" / IMAGES[a.variant]
    # the benches' order: each law, fine then with coarse steps (figures per step of dt)
    order = ("ls", "ls coarse", "lugre", "lugre coarse")
    for name, seg, pcs in zip(order, segments, at_pc):
        total = sum(n for k, n in seg.items() if " <- " not in k)
        print(f"== {a.target} {a.variant} {name}: {total / BENCH_STEPS:.0f} instructions per step")
        for sym, n in [x for x in seg.most_common() if " <- " not in x[0]][: a.top]:
            print(f"   {n / BENCH_STEPS:8.1f}  {100 * n / total:5.1f} %  {sym}")
        print("   libgcc's helpers by caller:")
        for sym, n in [x for x in seg.most_common() if " <- " in x[0]][: a.top]:
            print(f"   {n / BENCH_STEPS:8.1f}  {100 * n / total:5.1f} %  {sym}")
        if a.lines:
            print(f"   {a.lines} by source line:")
            for where, n in source_lines(image, pcs).most_common(a.top):
                print(f"   {n / BENCH_STEPS:8.1f}  {where}")


if __name__ == "__main__":
    main()
