#!/usr/bin/env python3
"""Writes the first SECONDS of an LCM log (by the events' own timestamps) to a new log.

    cut_log.py LOG OUT SECONDS

Every event whose timestamp is within SECONDS of the first event's is copied as it is, in order
(the event numbers stay those of the original). The live tests play such a cut of Plaza 1: the
same channels, rates and message sizes as the whole log, in a quarter of the time. Exit 2 on a
usage or file error, or a log that is not LCM's format. Python standard library only.
"""
import struct
import sys

SYNC = 0xEDA1DA01
HEADER = struct.Struct(">IqqII")  # sync, event number, utime, channel length, data length


def main():
    if len(sys.argv) != 4:
        sys.stderr.write(__doc__)
        return 2
    source, target, seconds = sys.argv[1], sys.argv[2], float(sys.argv[3])
    with open(source, "rb") as f:
        log = f.read()
    out = bytearray()
    offset, first, kept = 0, None, 0
    while offset + HEADER.size <= len(log):
        sync, _, utime, channel_len, data_len = HEADER.unpack_from(log, offset)
        end = offset + HEADER.size + channel_len + data_len
        if sync != SYNC or end > len(log):
            sys.stderr.write(f"cut_log.py: {source}: not an LCM log event at byte {offset}\n")
            return 2
        if first is None:
            first = utime
        if utime - first > seconds * 1e6:
            break
        out += log[offset:end]
        kept += 1
        offset = end
    with open(target, "wb") as f:
        f.write(out)
    print(f"cut_log.py: {kept} events of the first {seconds:g} s of {source}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
