"""Node parameters: one declaration per ``~param`` with its default, unit, limits and doc.

Every node lists its parameters once as a tuple of :class:`Param` in its pure module; the node
reads them with :func:`read_params`, the launch files mirror the defaults as ``<arg>`` and the
README table is printed by :func:`markdown_table` (a unit test keeps all three in step).
A bad value (wrong type, NaN, out of range, not a choice) is reported and replaced by the
default, so a typo in a launch file never takes a node down.
"""
import math
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any, Callable, Optional, Sequence, Tuple


@dataclass(frozen=True)
class Param:
    """One private node parameter.

    ``default`` fixes the type (bool, int, float or str). ``minimum``/``maximum`` bound numbers
    (inclusive); ``choices`` restricts strings.
    """

    name: str
    default: Any
    doc: str
    minimum: Optional[float] = None
    maximum: Optional[float] = None
    choices: Optional[Tuple[str, ...]] = None

    def coerce(self, value):
        """Return ``value`` converted to this parameter's type, or raise ValueError saying why."""
        kind = type(self.default)
        if kind is bool:
            if isinstance(value, bool):
                return value
            if isinstance(value, str) and value.lower() in ('true', 'false'):
                return value.lower() == 'true'
            raise ValueError('expected true or false, got %r' % (value,))
        if kind in (int, float):
            if isinstance(value, bool):
                raise ValueError('expected a number, got %r' % (value,))
            try:
                number = float(value)
            except (TypeError, ValueError):
                raise ValueError('expected a number, got %r' % (value,))
            if not math.isfinite(number):
                raise ValueError('expected a finite number, got %r' % (value,))
            if kind is int:
                if number != int(number):
                    raise ValueError('expected a whole number, got %r' % (value,))
                number = int(number)
            if self.minimum is not None and number < self.minimum:
                raise ValueError('%r is below the minimum %r' % (value, self.minimum))
            if self.maximum is not None and number > self.maximum:
                raise ValueError('%r is above the maximum %r' % (value, self.maximum))
            return number
        text = str(value)
        if self.choices is not None and text not in self.choices:
            raise ValueError('%r is not one of %s' % (value, ', '.join(self.choices)))
        return text


def read_params(specs: Sequence[Param], get_param: Callable[[str, Any], Any],
                warn: Callable[[str], None]) -> SimpleNamespace:
    """Read every ``~name`` in ``specs`` through ``get_param(name, default)``.

    Invalid values are reported through ``warn`` and replaced by the default.
    """
    values = {}
    for spec in specs:
        raw = get_param('~' + spec.name, spec.default)
        try:
            values[spec.name] = spec.coerce(raw)
        except ValueError as error:
            warn('parameter ~%s: %s; using the default %r' % (spec.name, error, spec.default))
            values[spec.name] = spec.default
    return SimpleNamespace(**values)


def defaults(specs: Sequence[Param]) -> SimpleNamespace:
    """The default of every parameter in ``specs``, by name (for tools that mirror a node)."""
    return SimpleNamespace(**{spec.name: spec.default for spec in specs})


def launch_value(value) -> str:
    """The text a launch file's ``<arg default=...>`` holds for ``value``."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    return str(value)


def markdown_table(specs: Sequence[Param]) -> str:
    """The README table of ``specs``: name, default, meaning."""
    rows = ['| parameter | default | meaning |', '|---|---|---|']
    for spec in specs:
        default = launch_value(spec.default)
        rows.append('| `~%s` | `%s` | %s |' % (spec.name, default if default else '""', spec.doc))
    return '\n'.join(rows)
