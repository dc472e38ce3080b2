"""Parameter declarations: coercion, validation and fallback to defaults."""
import math

import pytest

from can_seeker.params import Param, defaults, launch_value, markdown_table, read_params

SPECS = (
    Param('rate', 20.0, 'loop rate (Hz)', minimum=0.1, maximum=1000.0),
    Param('width', 320, 'image width (px)', minimum=1),
    Param('gui', False, 'open the GUI'),
    Param('renderer', 'auto', 'renderer', choices=('auto', 'egl', 'tiny')),
)


def read(given):
    warnings = []
    values = read_params(SPECS, lambda name, default: given.get(name, default), warnings.append)
    return values, warnings


def test_defaults_when_nothing_is_set():
    values, warnings = read({})
    assert (values.rate, values.width, values.gui, values.renderer) == (20.0, 320, False, 'auto')
    assert warnings == []


def test_valid_values_are_converted_to_the_declared_type():
    values, warnings = read({'~rate': 5, '~width': '640', '~gui': 'true', '~renderer': 'egl'})
    assert values.rate == 5.0 and isinstance(values.rate, float)
    assert values.width == 640 and isinstance(values.width, int)
    assert values.gui is True and values.renderer == 'egl'
    assert warnings == []


@pytest.mark.parametrize('name,bad', [
    ('~rate', float('nan')), ('~rate', float('inf')), ('~rate', 0.0), ('~rate', 'fast'),
    ('~rate', True), ('~width', 3.5), ('~width', -1), ('~gui', 'maybe'), ('~renderer', 'vulkan'),
])
def test_bad_values_warn_and_fall_back_to_the_default(name, bad):
    values, warnings = read({name: bad})
    spec = next(s for s in SPECS if '~' + s.name == name)
    assert getattr(values, spec.name) == spec.default
    assert len(warnings) == 1 and name in warnings[0]


def test_nan_message_names_the_problem():
    _, warnings = read({'~rate': math.nan})
    assert 'finite' in warnings[0]


def test_launch_value_and_markdown_table():
    assert launch_value(True) == 'true' and launch_value(0.5) == '0.5' and launch_value(7) == '7'
    table = markdown_table(SPECS)
    assert '| `~gui` | `false` | open the GUI |' in table
    assert table.count('\n') == len(SPECS) + 1


def test_defaults_by_name():
    values = defaults(SPECS)
    assert (values.rate, values.width, values.gui, values.renderer) == (20.0, 320, False, 'auto')
