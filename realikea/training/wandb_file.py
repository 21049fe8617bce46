"""Read an offline wandb run back from its `run-*.wandb` file (wandb 0.31 ships no Python
reader), to check what a run sent: `wandb_history(file)` -> {tag: {step: value}}.

The file is a log of 32 KiB blocks after a 7-byte header (":W&B", magic 0xBEE1, version); each
block holds chunks (crc32, length, type) of protobuf `Record`s, a record longer than a block's
rest split as FIRST, MIDDLE..., LAST; a block's tail too short for a chunk header is padding.
A chunk's crc32 runs over its type byte, then its bytes. A file wandb is still writing ends in a
chunk whose bytes are not all there yet: it is read up to its last whole record.
"""

from __future__ import annotations

import json
import struct
import zlib
from pathlib import Path

from realikea.errors import RealIkeaError

HEADER = struct.Struct("<4sHB")
CHUNK = struct.Struct("<IHB")
BLOCK = 32 * 1024
FULL, FIRST, MIDDLE, LAST = 1, 2, 3, 4


def wandb_records(path: Path) -> list:
    """Every protobuf `Record` in a `.wandb` run file, in order."""
    from wandb.proto import wandb_internal_pb2

    data = Path(path).read_bytes()
    if len(data) < HEADER.size or HEADER.unpack_from(data)[:2] != (b":W&B", 0xBEE1):
        raise RealIkeaError(f"{path} is not a wandb run file")
    records, pieces, pos = [], [], HEADER.size
    while pos + CHUNK.size <= len(data):
        if BLOCK - pos % BLOCK < CHUNK.size:
            pos += BLOCK - pos % BLOCK
            continue
        crc, length, kind = CHUNK.unpack_from(data, pos)
        if kind == 0 or pos + CHUNK.size + length > len(data):  # nothing, or not all, written yet
            break
        chunk = data[pos + CHUNK.size : pos + CHUNK.size + length]
        if zlib.crc32(chunk, zlib.crc32(bytes([kind]))) != crc:
            raise RealIkeaError(f"{path}: the chunk at byte {pos} fails its crc32 check")
        pieces.append(chunk)
        pos += CHUNK.size + length
        if kind in (FULL, LAST):
            record = wandb_internal_pb2.Record()
            record.ParseFromString(b"".join(pieces))
            records.append(record)
            pieces = []
    return records


def wandb_history(path: Path) -> dict[str, dict[int, float]]:
    """tag -> {step: value} of the run's history rows."""
    history: dict[str, dict[int, float]] = {}
    for record in wandb_records(path):
        if record.WhichOneof("record_type") != "history":
            continue
        step = record.history.step.num
        for item in record.history.item:
            key = item.key or "/".join(item.nested_key)
            history.setdefault(key, {})[step] = json.loads(item.value_json)
    return history


def run_file(run_dir: Path) -> Path:
    """The `.wandb` file of the one offline wandb run under a training run's folder."""
    found = sorted(Path(run_dir).glob("wandb/offline-run-*/run-*.wandb"))
    if len(found) != 1:
        raise RealIkeaError(f"{run_dir}: expected one offline wandb run, found {len(found)}")
    return found[0]
