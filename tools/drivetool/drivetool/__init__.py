"""drivetool: the host side of the drive's link (firmware/link/link_protocol.md)."""
from .drive import Drive, LinkError, NoAnswer, Refused, UsageError  # noqa: F401

__version__ = "1.0"
