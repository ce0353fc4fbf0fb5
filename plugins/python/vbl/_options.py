"""Render options through the library's options table (vbl_render_option_count/desc/set/get):
the binding never mirrors vbl_render_options. Internal: `vbl.RENDER_OPTIONS` and keyword
arguments of `vbl.render` are the public face."""

import ctypes
import os

from . import _native as N
from .errors import argument_error, check, decode


def encode(text):
    if text is None:
        return None
    return os.fsencode(text) if not isinstance(text, bytes) else text


def _option_rows():
    rows = []
    for index in range(N._option_count()):
        d = N._option_desc(index).contents
        rows.append({"name": decode(d.name), "key": decode(d.key), "flag": decode(d.flag),
                     "type": decode(d.type_name), "default": d.default_value, "min": d.min, "max": d.max,
                     "flags": d.flags, "choices": decode(d.choices).split("|") if d.choices else None,
                     "effect": d.effect, "help": decode(d.help)})
    return rows


# Every render option as the library describes it (name, key, flag, type, default, min, max,
# choices, help), in table order.
RENDER_OPTIONS = tuple(_option_rows())
# The settable fields of vbl_render_options, in table order (render() keyword arguments).
RENDER_OPTION_FIELDS = tuple(row["name"] for row in RENDER_OPTIONS)
_OPTION_TYPES = {row["name"]: row["type"] for row in RENDER_OPTIONS}
_OPTION_CHOICES = {row["name"]: row["choices"] for row in RENDER_OPTIONS if row["choices"]}


class Options:
    """A vbl_render_options the library allocates."""

    def __init__(self):
        handle = N._P()
        check(N._options_create(ctypes.byref(handle)))
        self.handle = handle

    def __del__(self):
        if getattr(self, "handle", None) and N._options_destroy is not None:
            N._options_destroy(self.handle)
            self.handle = None

    def set(self, name, value):
        choices = _OPTION_CHOICES.get(name)
        if choices and isinstance(value, int) and not isinstance(value, bool) and 0 <= value < len(choices):
            value = choices[value]  # an enum by its number, as the struct holds it
        if isinstance(value, bool):
            text = "true" if value else "false"
        elif isinstance(value, float):
            text = repr(value)
        else:
            text = str(value)
        check(N._option_set(self.handle, encode(name), encode(text)))

    def get(self, name):
        buffer = ctypes.create_string_buffer(256)
        check(N._option_get(self.handle, encode(name), buffer, len(buffer)))
        text = decode(buffer.value)
        kind = _OPTION_TYPES[name]
        if kind in ("int", "uint64"):
            return int(text)
        if kind == "double":
            return float(text)
        if kind == "bool":
            return text == "true"
        return text

    def apply(self, overrides, where):
        for name, value in overrides.items():
            if name not in RENDER_OPTION_FIELDS:
                raise argument_error("%s: unknown option %r (options: %s)" % (where, name, ", ".join(RENDER_OPTION_FIELDS)))
            if value is not None:
                self.set(name, value)

    def hash(self):
        buffer = ctypes.create_string_buffer(64)
        N._options_hash(self.handle, buffer, len(buffer))
        return decode(buffer.value)

    def to_dict(self):
        return {name: self.get(name) for name in RENDER_OPTION_FIELDS}
