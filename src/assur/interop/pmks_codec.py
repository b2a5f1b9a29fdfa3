"""The text encoding of PMKS+ share links and ``.pmks`` files (https://app.pmksplus.com), as documented by the
transcoders of PMKS-Web/PMKSWeb (production) and PMKS-Web/Planar-Mechanism-Kinematic-Simulator (current).

A link is ``https://app.pmksplus.com/?BODY`` and a ``.pmks`` file holds ``BODY``::

    BODY = BOOLS . DECIMALS . INTS . ENUMS . JOINT. … . LINK. … . FORCE. … . ACTIVE [. TRAILING] CHECK [*DIGEST]

Numbers are integers in a base-64 alphabet (``0-9A-Za-z_-``), a leading ``0`` marking a negative one; decimals are
thousandths. Flags pack six to a character. ``CHECK`` is one character of ``0-9A-Za-z``: the body's length modulo
62. The current format appends ``*`` and a 6-character FNV-1a digest (base 62) of the body with its check, and may
carry a trailing section with exact values (``PJ<id>~<field>~<value>``) where thousandths lose digits.
"""
from __future__ import annotations

from ..errors import SpecError

ALPHABET = "0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz_-"
CHECK_CHARS = ALPHABET[:62]
DIGEST_LENGTH = 6
#: the longest body read (characters): a drawing of a thousand joints fits several times over
MAX_BODY = 1024 * 1024


def to_int(text: str, where: str, positive: bool = False) -> int:
    """A base-64 integer (a leading ``0`` marks a negative number unless ``positive``)."""
    if len(text) > 12:
        raise SpecError([(where, f"{text!r} is too long a number")])
    neg = not positive and text[:1] == "0" and len(text) > 1
    value = 0
    for ch in text[1:] if neg else text:
        k = ALPHABET.find(ch)
        if k < 0:
            raise SpecError([(where, f"{text!r} is not a number of the link's alphabet")])
        value = value * 64 + k
    return -value if neg else value


def from_int(value: int) -> str:
    """The base-64 text of an integer (negative: a leading ``0``)."""
    n, digits = abs(int(value)), ""
    while True:
        digits = ALPHABET[n % 64] + digits
        n //= 64
        if n == 0:
            break
    return ("0" + digits) if value < 0 else digits


def to_decimal(text: str, where: str) -> float:
    """A decimal token (thousandths); empty reads 0 as in PMKS+."""
    return to_int(text, where) / 1000.0 if text else 0.0


def from_decimal(value: float) -> str:
    """A decimal as thousandths (rounded half away from zero on the magnitude, as ``Math.round`` on positives)."""
    import math
    return from_int(math.floor(value * 1000 + 0.5))


def unpack_flags(text: str, count: int, where: str) -> list[bool]:
    """``count`` flags packed in ``text`` (bit i is flag i)."""
    bits = to_int(text, where, positive=True) if text else 0
    return [bool(bits >> i & 1) for i in range(count)]


def pack_flags(flags) -> str:
    """Flags packed into ceil(n / 6) characters."""
    bits = sum(1 << i for i, f in enumerate(flags) if f)
    width = -(-len(flags) // 6)
    return from_int(bits).rjust(width, "0")


def checksum(body: str) -> str:
    """The length check character of a body."""
    return CHECK_CHARS[len(body) % 62]


def digest(text: str) -> str:
    """The 6-character FNV-1a (32-bit) digest of ``text`` in the check alphabet, most significant first."""
    h = 0x811C9DC5
    for ch in text:
        for unit in _utf16_units(ch):
            h = ((h ^ unit) * 0x01000193) & 0xFFFFFFFF
    out = ""
    for _ in range(DIGEST_LENGTH):
        out = CHECK_CHARS[h % 62] + out
        h //= 62
    return out


def _utf16_units(ch: str):
    """The UTF-16 code units of one character (what JavaScript's ``charCodeAt`` walks)."""
    data = ch.encode("utf-16-le")
    return [int.from_bytes(data[i:i + 2], "little") for i in range(0, len(data), 2)]


def unwrap(text: str) -> str:
    """The body of a share link or ``.pmks`` file, its checks verified and removed. SpecError for a truncated or
    damaged link (it would open a different mechanism)."""
    from urllib.parse import unquote
    text = text.strip()
    if len(text) > MAX_BODY:
        raise SpecError([("", f"a PMKS+ link longer than {MAX_BODY} characters is not read")])
    if "?" in text:
        text = text.split("?", 1)[1]
    text = unquote(text).strip()
    if text.startswith("pmks2:") or "document=pmks2" in text:
        raise SpecError([("", "a PMKS+ native document (pmks2:…, the development editor's format) is not read; "
                              "share the mechanism from the released PMKS+ (app.pmksplus.com) instead")])
    if len(text) < 2:
        raise SpecError([("", "the PMKS+ link is empty or truncated")])
    mark = text.rfind("*")
    if mark >= 0 and len(text) - mark - 1 == DIGEST_LENGTH and all(c in CHECK_CHARS for c in text[mark + 1:]):
        checked, dig = text[:mark], text[mark + 1:]
        if digest(checked) != dig:
            raise SpecError([("", "the PMKS+ link is damaged: its digest does not match its content")])
        text = checked
    body, check = text[:-1], text[-1]
    if checksum(body) != check:
        raise SpecError([("", f"the PMKS+ link is truncated or damaged: its length check is {check!r}, "
                              f"a body of {len(body)} characters needs {checksum(body)!r}")])
    return body


class Tokens:
    """The disassembler of a body: characters and delimited tokens, in order (empty past the end)."""

    def __init__(self, text: str):
        self.rest = text

    def empty(self) -> bool:
        return not self.rest

    def peek(self) -> str:
        return self.rest[:1]

    def char(self) -> str:
        c, self.rest = self.rest[:1], self.rest[1:]
        return c

    def token(self, delimiter: str = ",") -> str:
        i = self.rest.find(delimiter)
        if i < 0:
            t, self.rest = self.rest, ""
        else:
            t, self.rest = self.rest[:i], self.rest[i + 1:]
        return t


__all__ = ["ALPHABET", "CHECK_CHARS", "Tokens", "checksum", "digest", "from_decimal", "from_int", "pack_flags",
           "to_decimal", "to_int", "unpack_flags", "unwrap"]
