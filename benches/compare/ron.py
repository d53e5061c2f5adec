"""A reader for the subset of RON that Penumbra's scene files use.

Values come back as plain Python data: a struct or enum variant with named fields is a
`Struct` (its name, or `None` for an anonymous `( ... )`, and a dict of fields), a tuple is a
Python tuple, a list a list, a string a str, a number an int or float, and a bare identifier
(`Jittered`, `None`, `true`) an `Ident`. Comments (`//` and `/* */`) and extension
attributes (`#![enable(...)]`) are skipped.
"""

from dataclasses import dataclass, field


class Ident(str):
    """A bare identifier such as `Jittered` or `None`."""


@dataclass
class Struct:
    """`Name(field: value, ...)`, or `(field: value, ...)` with `name` None."""

    name: str | None
    fields: dict = field(default_factory=dict)

    def get(self, key, default=None):
        """The field `key`, or `default` when the file leaves it out."""
        return self.fields.get(key, default)

    def __getitem__(self, key):
        return self.fields[key]


class RonError(ValueError):
    """Malformed RON, with the line it was found on."""


def loads(text):
    """Parses one RON value from `text`."""
    parser = _Parser(text)
    value = parser.value()
    parser.skip_blank()
    if parser.pos != len(text):
        parser.fail("trailing text")
    return value


def load(path):
    """Parses the RON file at `path`."""
    with open(path, encoding="utf-8") as f:
        return loads(f.read())


class _Parser:
    def __init__(self, text):
        self.text = text
        self.pos = 0

    def fail(self, what):
        line = self.text.count("\n", 0, self.pos) + 1
        raise RonError(f"line {line}: {what}")

    def skip_blank(self):
        text = self.text
        while self.pos < len(text):
            c = text[self.pos]
            if c.isspace():
                self.pos += 1
            elif text.startswith("//", self.pos):
                end = text.find("\n", self.pos)
                self.pos = len(text) if end < 0 else end + 1
            elif text.startswith("#![", self.pos):
                # An extension attribute such as `#![enable(implicit_some)]`.
                end = text.find("]", self.pos + 3)
                if end < 0:
                    self.fail("unclosed attribute")
                self.pos = end + 1
            elif text.startswith("/*", self.pos):
                end = text.find("*/", self.pos)
                if end < 0:
                    self.fail("unclosed comment")
                self.pos = end + 2
            else:
                return

    def peek(self):
        self.skip_blank()
        return self.text[self.pos] if self.pos < len(self.text) else ""

    def expect(self, c):
        if self.peek() != c:
            self.fail(f"expected {c!r}")
        self.pos += 1

    def ident(self):
        start = self.pos
        while self.pos < len(self.text) and (self.text[self.pos].isalnum() or self.text[self.pos] == "_"):
            self.pos += 1
        return self.text[start : self.pos]

    def value(self):
        c = self.peek()
        if c == "(":
            return self.parens(None)
        if c == "[":
            return self.sequence("[", "]")
        if c == '"':
            return self.string()
        if c == "-" or c == "+" or c == "." or c.isdigit():
            return self.number()
        if c.isalpha() or c == "_":
            name = self.ident()
            if self.peek() == "(":
                return self.parens(name)
            return Ident(name)
        self.fail(f"unexpected {c!r}")

    def parens(self, name):
        """`( ... )`: named fields make a Struct, bare values a tuple (or `Some(x)`'s x)."""
        self.expect("(")
        save = self.pos
        self.skip_blank()
        key = self.ident()
        if key and self.peek() == ":":
            fields = {}
            self.pos = save
            while self.peek() != ")":
                self.skip_blank()
                key = self.ident()
                self.expect(":")
                fields[key] = self.value()
                if self.peek() == ",":
                    self.pos += 1
            self.pos += 1
            return Struct(name, fields)
        self.pos = save
        items = []
        while self.peek() != ")":
            items.append(self.value())
            if self.peek() == ",":
                self.pos += 1
        self.pos += 1
        if name == "Some" and len(items) == 1:
            return items[0]
        if name is not None:
            return Struct(name, {"values": tuple(items)})
        return tuple(items)

    def sequence(self, open_, close):
        self.expect(open_)
        items = []
        while self.peek() != close:
            if not self.peek():
                self.fail(f"expected {close!r}")
            items.append(self.value())
            if self.peek() == ",":
                self.pos += 1
        self.pos += 1
        return items

    def string(self):
        self.expect('"')
        out = []
        while self.pos < len(self.text) and self.text[self.pos] != '"':
            c = self.text[self.pos]
            if c == "\\":
                self.pos += 1
                c = self.text[self.pos]
            out.append(c)
            self.pos += 1
        self.expect('"')
        return "".join(out)

    def number(self):
        start = self.pos
        while self.pos < len(self.text) and (
            self.text[self.pos] in "+-.eE_" or self.text[self.pos].isdigit()
        ):
            self.pos += 1
        raw = self.text[start : self.pos].replace("_", "")
        try:
            return int(raw)
        except ValueError:
            try:
                return float(raw)
            except ValueError:
                self.fail(f"bad number {raw!r}")


def dumps(value, indent=""):
    """RON text of a value as `loads` returns it (floats keep every digit)."""
    inner = indent + "    "
    if isinstance(value, Struct):
        if set(value.fields) == {"values"} and value.name is not None:
            return "%s(%s)" % (value.name, ", ".join(dumps(v, inner) for v in value.fields["values"]))
        body = ",\n".join(f"{inner}{key}: {dumps(v, inner)}" for key, v in value.fields.items())
        return "%s(\n%s,\n%s)" % (value.name or "", body, indent) if body else "%s()" % (value.name or "")
    if isinstance(value, tuple):
        return "(%s)" % ", ".join(dumps(v, inner) for v in value)
    if isinstance(value, list):
        if not value:
            return "[]"
        return "[\n%s,\n%s]" % (",\n".join(inner + dumps(v, inner) for v in value), indent)
    if isinstance(value, Ident):
        return str(value)
    if isinstance(value, str):
        return '"%s"' % value.replace("\\", "\\\\").replace('"', '\\"')
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, int):
        return str(value)
    raise TypeError(f"no RON form for {value!r}")
