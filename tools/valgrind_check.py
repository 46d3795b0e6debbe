#!/usr/bin/env python3
"""Reads a valgrind memcheck log (--leak-check=full --show-leak-kinds=all) and
fails if it shows a memory error, a block definitely or indirectly lost, or a
block Embree allocated that is still held at exit: a leaked Embree handle.

Embree keeps pointers to its devices and scenes in TBB's global state, so a
leaked handle is "still reachable", not "definitely lost"; it is found by
the rtc* call that allocated it. Blocks TBB itself allocates (its scheduler
state, a worker thread's TLS block, which valgrind calls "possibly lost")
stay until exit by design and are not counted.

Run valgrind with --errors-for-leak-kinds=definite,indirect, so that the
ERROR SUMMARY counts memory errors and real leaks only.

Usage: valgrind_check.py LOG
"""

import re
import sys


def records(text):
    """Each loss record: (its heading, its stack frames)."""
    for block in re.split(r"==\d+== \n", text):
        lines = block.splitlines()
        for i, line in enumerate(lines):
            if "blocks are" in line and "in loss record" in line:
                frames = [l for l in lines[i + 1:] if re.search(r"(at|by) 0x", l)]
                yield line.split("== ", 1)[-1], frames


ALLOCATORS = re.compile(
    r"(malloc|calloc|realloc|memalign|posix_memalign|aligned_alloc|operator new)"
)


def allocated_by_embree(frames):
    """Whether the first frame past the allocator is Embree's own code (not
    TBB's, and not a Rust callback that Embree called)."""
    for frame in frames:
        if (ALLOCATORS.search(frame) and "vgpreload" in frame) or "rtld-malloc" in frame:
            continue
        return "libembree" in frame
    return False


def main(path):
    text = open(path, encoding="utf-8", errors="replace").read()
    problems = []
    errors = re.findall(r"ERROR SUMMARY: (\d+) errors", text)
    if not errors:
        problems.append("no ERROR SUMMARY: did valgrind run?")
    elif int(errors[-1]) > 0:
        problems.append(f"{errors[-1]} memory errors")
    for heading, frames in records(text):
        stack = "\n".join(frames)
        if "definitely lost" in heading or "indirectly lost" in heading:
            problems.append(heading)
        elif allocated_by_embree(frames):
            call = re.search(r"\brtc[A-Z]\w*", stack)
            name = call.group(0) if call else "Embree"
            problems.append(f"{heading} (Embree handle from {name} never released)")
    for p in problems:
        print(f"valgrind_check: {p}")
    if not problems:
        print("valgrind_check: no memory errors, no leaks, no Embree handle left")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
