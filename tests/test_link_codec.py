"""tools/drivetool's codec against the golden vectors of tests/link_vectors.txt
(shared with tests/test_link_codec.c) and its receiver's resync."""
import os
import sys
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "tools", "drivetool"))

from drivetool import codec  # noqa: E402

VECTORS = os.path.join(HERE, "link_vectors.txt")


def _hex(s):
    return b"" if s == "-" else bytes.fromhex(s)


class GoldenVectors(unittest.TestCase):
    def setUp(self):
        with open(VECTORS) as f:
            self.lines = [ln.split() for ln in f if ln.strip() and not ln.startswith("#")]

    def test_crc(self):
        rows = [r for r in self.lines if r[0] == "crc"]
        self.assertGreaterEqual(len(rows), 5)
        for _k, data, want in rows:
            self.assertEqual(codec.crc16(_hex(data)), int(want, 16))

    def test_cobs(self):
        rows = [r for r in self.lines if r[0] == "cobs"]
        self.assertGreaterEqual(len(rows), 11)
        for _k, data, enc in rows:
            self.assertEqual(codec.cobs_encode(_hex(data)).hex(), enc)
            self.assertEqual(codec.cobs_decode(_hex(enc)), _hex(data))

    def test_frames(self):
        rows = [r for r in self.lines if r[0] == "frame"]
        types = set()
        for _k, t, s, payload, wire in rows:
            self.assertEqual(codec.frame_encode(int(t, 16), int(s, 16), _hex(payload)).hex(), wire)
            rx = codec.Receiver()
            self.assertEqual(rx.feed(_hex(wire)), [(int(t, 16), int(s, 16), _hex(payload))])
            types.add(int(t, 16) & 0x7F)
        # every request type 0x01..0x0A and the unsolicited ones
        self.assertTrue(set(range(1, 11)) | {0x40, 0x41} <= types)

    def test_bad_rejected(self):
        for r in (r for r in self.lines if r[0] == "bad"):
            rx = codec.Receiver()
            self.assertEqual(rx.feed(_hex(r[1])), [])
            self.assertEqual(rx.errors, 1)


class Receiver(unittest.TestCase):
    def test_resync_after_garbage_within_one_frame(self):
        good = codec.frame_encode(3, 9, b"\x00\x07")
        rx = codec.Receiver()
        self.assertEqual(rx.feed(b"\x55\x13\xff" + good), [])   # the garbage spoils the first block only
        self.assertEqual(rx.feed(good), [(3, 9, b"\x00\x07")])
        flipped = bytearray(good)
        flipped[2] ^= 4
        self.assertEqual(rx.feed(bytes(flipped) + good), [(3, 9, b"\x00\x07")])


if __name__ == "__main__":
    unittest.main()
