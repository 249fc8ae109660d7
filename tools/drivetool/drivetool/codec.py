"""The link's framing (firmware/link/link_protocol.md), no dependencies: CRC-16/
CCITT-FALSE, COBS, frames [type, seq, payload, crc lo, crc hi] COBS-encoded
and ended by 0x00, and a receiver that resyncs at every 0x00."""
import struct

PAYLOAD_MAX = 240
FRAME_OVERHEAD = 8          # a frame's bytes on the wire beyond its payload: type, seq, CRC, COBS codes, 0x00

# frame types
HELLO, LIST_VARS, READ, WRITE, ACTION = 0x01, 0x02, 0x03, 0x04, 0x05
STREAM_SET, CAPTURE_ARM, CAPTURE_STATUS, CAPTURE_READ, PING = 0x06, 0x07, 0x08, 0x09, 0x0A
EVENT, STREAM, NOTICE, REPLY = 0x40, 0x41, 0x42, 0x80
# NOTICE's code (then text): why the port closes this client
NOTICE_HELD, NOTICE_IDLE = 1, 2

# reply status (first payload byte)
ST_OK, ST_REFUSED, ST_BAD_REQUEST, ST_UNKNOWN_ID, ST_ACCESS, ST_UNKNOWN_TYPE, ST_BUSY = range(7)
STATUS_TEXT = {
    ST_OK: "ok", ST_REFUSED: "refused", ST_BAD_REQUEST: "bad request", ST_UNKNOWN_ID: "unknown variable id",
    ST_ACCESS: "not writable now", ST_UNKNOWN_TYPE: "unknown request type", ST_BUSY: "busy",
}

# variable types and access
T_U16, T_U32, T_F32 = 0, 1, 2
ACC_READ, ACC_WRITE, ACC_WRITE_STOPPED = 0, 1, 2
# actions
ACT_START, ACT_STOP, ACT_FAULT_RESET, ACT_QUIT, ACT_COMMISSION, ACT_LEVEL = 1, 2, 3, 4, 5, 6   # LEVEL carries the level
ACT_SAVE = 7                # the parameters into the drive's store (link_nv.h)
# capture triggers and states
TRIG_FORCED, TRIG_ABOVE, TRIG_BELOW, TRIG_FAULT, TRIG_STATE = range(5)
CAP_IDLE, CAP_PRE, CAP_POST, CAP_DONE = range(4)
# a capture channel's format (CAPTURE_STATUS): int16 counts, or the float32 value
CAP_I16, CAP_F32 = 0, 1


def crc16(data, crc=0xFFFF):
    """CRC-16/CCITT-FALSE: poly 0x1021, init 0xFFFF, no reflection, no final xor."""
    for b in data:
        crc ^= b << 8
        for _ in range(8):
            crc = ((crc << 1) ^ 0x1021) if crc & 0x8000 else (crc << 1)
            crc &= 0xFFFF
    return crc


def cobs_encode(data):
    """COBS without the delimiter; a full 254-byte block at the end gets no empty block after it."""
    out = bytearray([0])
    code_at, code = 0, 1
    for i, b in enumerate(data):
        if b == 0:
            out[code_at] = code
            code_at, code = len(out), 1
            out.append(0)
        else:
            out.append(b)
            code += 1
            if code == 0xFF:
                out[code_at] = code
                if i + 1 == len(data):
                    return bytes(out)
                code_at, code = len(out), 1
                out.append(0)
    out[code_at] = code
    return bytes(out)


def cobs_decode(data):
    """Inverse of cobs_encode; ValueError on a zero inside or a block running past the end."""
    out = bytearray()
    i, n = 0, len(data)
    while i < n:
        code = data[i]
        if code == 0 or n - i < code:
            raise ValueError("bad COBS block")
        block = data[i + 1:i + code]
        if 0 in block:
            raise ValueError("zero inside a COBS block")
        out += block
        i += code
        if code < 0xFF and i < n:
            out.append(0)
    return bytes(out)


def frame_encode(ftype, seq, payload=b""):
    """A frame's wire bytes, delimiter included."""
    if len(payload) > PAYLOAD_MAX:
        raise ValueError(f"payload of {len(payload)} bytes, at most {PAYLOAD_MAX}")
    raw = bytes([ftype & 0xFF, seq & 0xFF]) + bytes(payload)
    raw += struct.pack("<H", crc16(raw))
    return cobs_encode(raw) + b"\x00"


def frame_decode(block):
    """One COBS block (no delimiter) -> (type, seq, payload); ValueError if bad."""
    raw = cobs_decode(block)
    if len(raw) < 4:
        raise ValueError("frame too short")
    if crc16(raw[:-2]) != struct.unpack("<H", raw[-2:])[0]:
        raise ValueError("bad CRC")
    return raw[0], raw[1], raw[2:-2]


class Receiver:
    """Bytes in, frames out; resyncs at every 0x00 with no timeouts."""

    MAX_BLOCK = PAYLOAD_MAX + 4 + 2

    def __init__(self):
        self.buf = bytearray()
        self.errors = 0

    def feed(self, data):
        frames = []
        for b in data:
            if b != 0:
                self.buf.append(b)
                continue
            block, self.buf = bytes(self.buf), bytearray()
            if not block:
                continue
            if len(block) > self.MAX_BLOCK:
                self.errors += 1
                continue
            try:
                frames.append(frame_decode(block))
            except ValueError:
                self.errors += 1
        return frames
