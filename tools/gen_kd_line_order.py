#!/usr/bin/env python3
"""Prints the two tables of src/accel/kdtree/trace/kd_line_order.h (the
SIMD line walk's visit order and left-pack), one 8-byte row per entry: byte
j of a row is a lane index."""


def key(x, s):
    # Front-to-back rank of exit x (path bits: level 0 = bit 2) when bit h
    # of s says position h's near child is its right one.
    b = lambda h: (s >> h) & 1
    return x ^ (b(0) << 2 | b(1 + (x >> 2)) << 1 | b(3 + (x >> 1)))


def rows(table):
    out = []
    for i in range(0, len(table), 3):
        out.append("    " + " ".join("0x%016xu," % sum(v << (8 * j) for j, v in enumerate(r))
                                      for r in table[i:i + 3]))
    return "\n".join(out)


back_to_front = []
for s in range(128):
    exit_of = [0] * 8
    for x in range(8):
        exit_of[key(x, s)] = x
    back_to_front.append([exit_of[7 - j] for j in range(8)])
left_pack = []
for m in range(256):
    lanes = [i for i in range(8) if m >> i & 1]
    left_pack.append(lanes + [0] * (8 - len(lanes)))
print("back_to_front:\n" + rows(back_to_front))
print("left_pack:\n" + rows(left_pack))
