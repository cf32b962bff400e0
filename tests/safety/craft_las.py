#!/usr/bin/env python3
"""tests/safety/craft_las.py: crafted LAS/LAZ files for cli_safety_test.sh, made from a
real file of ours (stdlib only). Usage: craft_las.py CASE IN OUT, CASE one of:
compressor1, compressor2 (the LASzip VLR's compressor), cut6, cut7 (the file cut 6 or 7
bytes into the chunk table), count_high (the table's chunk count with its high byte set),
layers_wrap (a chunk's layer sizes summing past 2^32), two_extra (a LAS with a second
extra bytes VLR of one byte), fewer_points (the header counting one point less)."""
import struct
import sys


def vlr_at(b, user):
    at = struct.unpack_from("<H", b, 94)[0]
    for _ in range(struct.unpack_from("<I", b, 100)[0]):
        if b[at + 2:at + 18].rstrip(b"\0") == user:
            return at
        at += 54 + struct.unpack_from("<H", b, at + 20)[0]
    raise SystemExit("no VLR " + user.decode())


def main():
    case, src, dst = sys.argv[1:4]
    b = bytearray(open(src, "rb").read())
    data_at = struct.unpack_from("<I", b, 96)[0]
    record = struct.unpack_from("<H", b, 105)[0]
    if case in ("compressor1", "compressor2"):
        struct.pack_into("<H", b, vlr_at(b, b"laszip encoded") + 54, int(case[-1]))
    elif case in ("cut6", "cut7"):
        table = struct.unpack_from("<q", b, data_at)[0]
        b = b[:table + int(case[-1])]
    elif case == "count_high":
        table = struct.unpack_from("<q", b, data_at)[0]
        b[table + 7] |= 0x80
    elif case == "layers_wrap":
        sizes = data_at + 8 + record + 4
        struct.pack_into("<II", b, sizes, 0xFFFFFFFF, 2)
    elif case == "two_extra":
        at = vlr_at(b, b"LASF_Spec")
        second = bytearray(b[at:at + 54 + 192])
        struct.pack_into("<H", second, 20, 192)
        second[54 + 2] = 1
        second[54 + 4:54 + 36] = b"other".ljust(32, b"\0")
        b = b[:data_at] + second + b[data_at:]
        struct.pack_into("<I", b, 96, data_at + len(second))
        struct.pack_into("<I", b, 100, struct.unpack_from("<I", b, 100)[0] + 1)
    elif case == "fewer_points":
        struct.pack_into("<Q", b, 247, struct.unpack_from("<Q", b, 247)[0] - 1)
    else:
        raise SystemExit("unknown case " + case)
    open(dst, "wb").write(b)


if __name__ == "__main__":
    main()
