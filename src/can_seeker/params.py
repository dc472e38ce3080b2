"""Node parameters: one declaration per ``~param`` with its default, unit, limits and doc.

Every node lists its parameters once as a tuple of :class:`Param` in its pure module; the node
reads them with :func:`read_params`, the launch files mirror the defaults as ``<arg>`` and the
table of docs/parameters.md is printed by :func:`markdown_table` (unit tests keep all three in
step).
A name may hold ``/``: ``~realism/preset`` is the parameter ``preset`` of the private
sub-namespace ``realism`` (as ROS drivers group a sensor's settings); it is read as
``config.realism.preset``. A name is either a value or a namespace, never both (ROS cannot hold
both).
A bad value (wrong type, NaN, out of range, not a choice) is reported and replaced by the
default, so a typo in a launch file never takes a node down, except for a safety bound (a speed
or acceleration limit, a clearance, a watchdog timeout; one with a declared ``safer`` side): no
default is safe in place of what the user asked for (a crawl must not become full speed), so
:func:`read_params` refuses the start.
"""
import difflib
import math
import re
from dataclasses import dataclass
from types import SimpleNamespace
from typing import Any, Callable, Iterable, List, Mapping, Optional, Sequence, Tuple

from can_seeker.health import OK, WARN, Health

SAFE_SIDES = ('lower', 'higher')
NAME = re.compile(r'[A-Za-z][A-Za-z0-9_]*(/[A-Za-z][A-Za-z0-9_]*)*')
"""A parameter name: words of letters, digits and _, a ``/`` between a namespace and a name."""


class UnsafeParamError(ValueError):
    """Safety bounds with invalid values: the node must not start (see :class:`Param` safer)."""


@dataclass(frozen=True)
class Param:
    """One private node parameter.

    ``default`` fixes the type (bool, int, float or str). ``minimum``/``maximum`` bound numbers
    (inclusive); ``choices`` restricts strings. ``safer`` ('lower' or 'higher') marks a number
    that bounds the robot's motion and says which side of it is the safe one.
    """

    name: str
    default: Any
    doc: str
    minimum: Optional[float] = None
    maximum: Optional[float] = None
    choices: Optional[Tuple[str, ...]] = None
    safer: Optional[str] = None

    def __post_init__(self):
        if not NAME.fullmatch(self.name):
            raise ValueError('~%s: a name is words of letters, digits and _, separated by / '
                             '(a namespace)' % (self.name,))
        if self.safer is not None and (self.safer not in SAFE_SIDES
                                       or type(self.default) not in (int, float)):
            raise ValueError('~%s: safer must be one of %s, on a number'
                             % (self.name, ', '.join(SAFE_SIDES)))

    @property
    def namespace(self) -> str:
        """The private sub-namespace the parameter is in (``realism`` of ``realism/preset``),
        '' at the top."""
        return self.name.rpartition('/')[0]

    @property
    def description(self) -> str:
        """The doc, with the safe side of a safety bound (the launch files' arg docs)."""
        if self.safer is None:
            return self.doc
        return '%s; safety bound, %s is safer: an invalid value stops the node' % (
            self.doc, self.safer)

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

    Invalid values are reported through ``warn`` and replaced by the default; invalid safety
    bounds raise :class:`UnsafeParamError` naming all of them.
    """
    values, refused = {}, []
    for spec in specs:
        raw = get_param('~' + spec.name, spec.default)
        try:
            values[spec.name] = spec.coerce(raw)
        except ValueError as error:
            if spec.safer is not None:
                refused.append('~%s: %s (a safety bound, %s is safer)'
                               % (spec.name, error, spec.safer))
                continue
            warn('parameter ~%s: %s; using the default %r' % (spec.name, error, spec.default))
            values[spec.name] = spec.default
    if refused:
        raise UnsafeParamError('invalid safety bounds, not starting: ' + '; '.join(refused))
    return nested(values)


def nested(values: Mapping[str, Any]) -> SimpleNamespace:
    """``values`` by name as attributes, a namespace's as a namespace of its own:
    ``{'seed': 3, 'realism/preset': 'harsh'}`` -> ``.seed``, ``.realism.preset``. ValueError
    for a name that is both a value and a namespace."""
    for name in values:
        parts = name.split('/')
        for depth in range(1, len(parts)):
            if '/'.join(parts[:depth]) in values:
                raise ValueError('~%s is a value and a namespace' % '/'.join(parts[:depth]))
    tree = {}
    for name, value in values.items():
        *namespaces, leaf = name.split('/')
        branch = tree
        for part in namespaces:
            branch = branch.setdefault(part, {})
        branch[leaf] = value

    def namespace(branch):
        return SimpleNamespace(**{key: namespace(value) if isinstance(value, dict) else value
                                  for key, value in branch.items()})
    return namespace(tree)


def defaults(specs: Sequence[Param], overrides: Optional[Mapping[str, Any]] = None
             ) -> SimpleNamespace:
    """The default of every parameter in ``specs``, by name as :func:`read_params` gives them
    (for tools that mirror a node), with ``overrides`` (full names: ``realism/preset``) put in
    as they are; ValueError for an override no spec declares."""
    values = {spec.name: spec.default for spec in specs}
    for name, value in (overrides or {}).items():
        if name not in values:
            raise ValueError(unknown_param_message(name, specs))
        values[name] = value
    return nested(values)


def unknown_param_message(name: str, specs: Sequence[Param], prefix: str = '~'
                          ) -> Optional[str]:
    """None when ``name`` (without the ``~``) is a parameter of ``specs``; else why it is not
    read, with the declared name it likely means: the one of the same last word (a parameter
    that moved into a namespace), else the closest spelling. A namespace given a value lists
    the parameters it holds. Names are shown after ``prefix`` (``sim/`` for a tool's
    ``NODE/PARAM``)."""
    names = [spec.name for spec in specs]
    if name in names:
        return None
    inside = [prefix + other for other in names if other.startswith(name + '/')]
    if inside:
        more = ', ... (%d in all)' % len(inside) if len(inside) > 3 else ''
        return '%s%s is a namespace, not a parameter: it holds %s%s' % (
            prefix, name, ', '.join(inside[:3]), more)
    leaf = name.rpartition('/')[2]
    likely = ([other for other in names if other.rpartition('/')[2] == leaf]
              or difflib.get_close_matches(name, names, n=1, cutoff=0.8))
    if not likely:
        return '%s%s is not a parameter' % (prefix, name)
    return '%s%s is not a parameter; did you mean %s?' % (
        prefix, name, ' or '.join(prefix + other for other in likely))


def unread_params(specs: Sequence[Param], names: Iterable[str]) -> List[Tuple[str, str]]:
    """(name, :func:`unknown_param_message`) of every name in ``names`` (the private
    parameters a node finds set, without the ``~``) that ``specs`` does not declare, by
    name."""
    return [(name, message) for name, message in ((name, unknown_param_message(name, specs))
                                                  for name in sorted(set(names))) if message]


def unread_health(unread: Sequence[Tuple[str, str]]) -> Health:
    """The status of a node's parameters: WARN while any set in its private namespace is not
    read (a setting that would otherwise be ignored without a word), each with what it likely
    means; OK when every one is read."""
    if not unread:
        return Health(OK, 'every parameter set is read')
    return Health(WARN, 'not read: %s' % ', '.join('~' + name for name, _ in unread),
                  tuple(('~' + name, message) for name, message in unread))


def by_namespace(specs: Sequence[Param]) -> List[Tuple[str, List[Param]]]:
    """(namespace, its parameters in order) of ``specs``: the top ('') first, then each
    namespace in the order it first appears (the reference's tables)."""
    groups = {'': []}
    for spec in specs:
        groups.setdefault(spec.namespace, []).append(spec)
    return [(namespace, group) for namespace, group in groups.items() if group]


def launch_value(value) -> str:
    """The text a launch file's ``<arg default=...>`` holds for ``value``."""
    if isinstance(value, bool):
        return 'true' if value else 'false'
    return str(value)


UNIT_SUFFIXES = (('_mps', 'm/s'), ('_deg', 'deg'), ('_hz', 'Hz'), ('_px', 'px'), ('_m', 'm'),
                 ('_s', 's'))
"""Name endings that state a parameter's unit (``camera_latency_s``), longest first."""
DOC_UNITS = ('m', 's', 'Hz', 'deg', 'px', 'K', '1', '1/s', 'm/s', 'rad/s', 'm/s^2', 'rad/s^2',
             'm/rad')
"""Units a doc may state in parentheses, before any comma or semicolon: ``(Hz, sim time)``."""
DOC_UNIT = re.compile(r'\(([^(),;]+)[,;)]')


def unit_of(spec: Param) -> str:
    """The unit the parameter's name ends in, else the first of :data:`DOC_UNITS` its doc states
    in parentheses, else '' (the reference names no unit the declaration does not state)."""
    for suffix, unit in UNIT_SUFFIXES:
        if spec.name.endswith(suffix):
            return unit
    for match in DOC_UNIT.finditer(spec.doc):
        if match.group(1).strip() in DOC_UNITS:
            return match.group(1).strip()
    return ''


def range_text(spec: Param) -> str:
    """The accepted values: ``min .. max`` (either side open), or the choices."""
    if spec.choices is not None:
        return ', '.join('`%s`' % choice for choice in spec.choices)
    if spec.minimum is None and spec.maximum is None:
        return ''
    return '%s .. %s' % ('' if spec.minimum is None else launch_value(spec.minimum),
                         '' if spec.maximum is None else launch_value(spec.maximum))


def _cell(text: str) -> str:
    return text.replace('|', '\\|')


def markdown_table(specs: Sequence[Param]) -> str:
    """The reference table of ``specs``: name, type, default, accepted range, unit, the safe side
    of a safety bound, and the doc."""
    rows = ['| parameter | type | default | range | unit | safe side | meaning |',
            '|---|---|---|---|---|---|---|']
    for spec in specs:
        default = launch_value(spec.default)
        rows.append('| `~%s` | %s | `%s` | %s | %s | %s | %s |' % (
            spec.name, type(spec.default).__name__, _cell(default) if default else '""',
            range_text(spec), unit_of(spec), spec.safer or '', _cell(spec.doc)))
    return '\n'.join(rows)


def parse_topics(text: str) -> Sequence[str]:
    """Topic names separated by spaces or commas, in order, without repeats."""
    names = []
    for name in text.replace(',', ' ').split():
        if name not in names:
            names.append(name)
    return tuple(names)
