"""Parameter declarations: coercion, validation and fallback to defaults."""
import math

import pytest

from can_seeker.health import OK, WARN
from can_seeker.params import (Param, UnsafeParamError, by_namespace, defaults, launch_value,
                               markdown_table, nested, range_text, read_params,
                               unknown_param_message, unit_of, unread_health, unread_params)

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
    assert '| `~gui` | bool | `false` |  |  |  | open the GUI |' in table
    assert '| `~rate` | float | `20.0` | 0.1 .. 1000.0 | Hz |  | loop rate (Hz) |' in table
    assert table.count('\n') == len(SPECS) + 1


def test_range_text_of_bounds_and_choices():
    assert range_text(SPECS[1]) == '1 .. '
    assert range_text(SPECS[3]) == '`auto`, `egl`, `tiny`'
    assert range_text(SPECS[2]) == ''


@pytest.mark.parametrize('name,doc,unit', [
    ('camera_latency_s', 'latency (frames)', 's'),
    ('motor_deadband_mps', 'deadband', 'm/s'),
    ('fov_deg', 'field of view', 'deg'),
    ('camera_rate', 'frame rate (Hz, sim time)', 'Hz'),
    ('track_gate', 'how far (m; 0 = no hysteresis)', 'm'),
    ('seam', 'a seam (REP-103) of the frame (m)', 'm'),
    ('dark_threshold', 'grey level (0-255)', ''),
    ('odom_noise', 'error (m per square root of m)', ''),
])
def test_the_unit_comes_from_the_name_or_the_doc(name, doc, unit):
    assert unit_of(Param(name, 1.0, doc)) == unit


def test_defaults_by_name():
    values = defaults(SPECS)
    assert (values.rate, values.width, values.gui, values.renderer) == (20.0, 320, False, 'auto')


SAFETY_SPECS = (
    Param('max_speed', 0.4, 'speed limit (m/s)', minimum=0.01, maximum=2.0, safer='lower'),
    Param('margin', 0.05, 'clearance (m)', minimum=0.0, maximum=1.0, safer='higher'),
    Param('gain', 1.5, 'gain (1/s)', minimum=0.05, maximum=10.0),
)


@pytest.mark.parametrize('given', [
    {'~max_speed': 0.005}, {'~max_speed': math.nan}, {'~max_speed': 'crawl'},
    {'~max_speed': True}, {'~margin': -0.1}, {'~margin': 2.0},
])
def test_an_invalid_safety_bound_refuses_the_start(given):
    with pytest.raises(UnsafeParamError) as refused:
        read_params(SAFETY_SPECS, lambda name, default: given.get(name, default), print)
    assert next(iter(given))[1:] in str(refused.value)


def test_every_invalid_safety_bound_is_named_at_once():
    given = {'~max_speed': 0.0, '~margin': math.nan, '~gain': 'x'}
    warnings = []
    with pytest.raises(UnsafeParamError) as refused:
        read_params(SAFETY_SPECS, lambda name, default: given.get(name, default),
                    warnings.append)
    assert 'max_speed' in str(refused.value) and 'margin' in str(refused.value)
    assert len(warnings) == 1 and '~gain' in warnings[0]


def test_valid_safety_bounds_are_taken_as_given():
    given = {'~max_speed': 0.01, '~margin': 1.0}
    values = read_params(SAFETY_SPECS, lambda name, default: given.get(name, default), print)
    assert (values.max_speed, values.margin, values.gain) == (0.01, 1.0, 1.5)


def test_the_safe_side_is_documented():
    assert 'lower is safer' in SAFETY_SPECS[0].description
    assert 'higher is safer' in SAFETY_SPECS[1].description
    assert SAFETY_SPECS[2].description == 'gain (1/s)'
    assert '| lower | ' in markdown_table(SAFETY_SPECS).splitlines()[2]


@pytest.mark.parametrize('kwargs', [
    dict(name='x', default=1.0, doc='d', safer='faster'),
    dict(name='x', default='a', doc='d', safer='lower'),
])
def test_a_safe_side_needs_a_number_and_a_direction(kwargs):
    with pytest.raises(ValueError):
        Param(**kwargs)


NAMESPACED = (
    Param('seed', 0, 'random seed', minimum=0),
    Param('lens/model', 'pinhole', 'lens model', choices=('pinhole', 'fisheye')),
    Param('lens/k1', -1.0, 'distortion k1; -1: the model\'s', minimum=-1.0, maximum=1.0),
    Param('light/kelvin', 6500.0, 'colour temperature (K)', minimum=1000.0),
)


def test_a_namespaced_parameter_is_read_by_its_full_name_into_a_namespace_of_its_own():
    given = {'~lens/model': 'fisheye', '~lens/k1': 'bent', '~seed': 4}
    asked, warnings = [], []

    def get_param(name, default):
        asked.append(name)
        return given.get(name, default)
    values = read_params(NAMESPACED, get_param, warnings.append)
    assert asked == ['~seed', '~lens/model', '~lens/k1', '~light/kelvin']
    assert (values.seed, values.lens.model, values.lens.k1, values.light.kelvin) \
        == (4, 'fisheye', -1.0, 6500.0)
    assert warnings == [
        "parameter ~lens/k1: expected a number, got 'bent'; using the default -1.0"]


def test_defaults_take_overrides_by_full_name_and_refuse_an_undeclared_one():
    values = defaults(NAMESPACED, {'lens/k1': -0.25, 'seed': 9})
    assert (values.seed, values.lens.model, values.lens.k1) == (9, 'pinhole', -0.25)
    assert defaults(NAMESPACED).lens.k1 == -1.0           # a fresh namespace every time
    with pytest.raises(ValueError, match=r'~k1 is not a parameter; did you mean ~lens/k1\?'):
        defaults(NAMESPACED, {'k1': 0.1})


def test_a_name_cannot_be_a_value_and_a_namespace():
    with pytest.raises(ValueError, match='~lens is a value and a namespace'):
        nested({'lens': 'pinhole', 'lens/k1': 0.1})
    with pytest.raises(ValueError, match='~lens is a value and a namespace'):
        read_params(NAMESPACED + (Param('lens', 'x', 'the lens'),), lambda name, default: default,
                    print)


@pytest.mark.parametrize('name', ['', 'lens/', '/lens', 'lens//k1', '~lens', 'lens k1', '1lens'])
def test_a_name_is_words_separated_by_slashes(name):
    with pytest.raises(ValueError):
        Param(name, 1.0, 'd')


def test_an_unknown_name_says_which_declared_one_it_likely_means():
    assert unknown_param_message('lens/k1', NAMESPACED) is None
    assert unknown_param_message('k1', NAMESPACED) == \
        '~k1 is not a parameter; did you mean ~lens/k1?'
    assert unknown_param_message('lens/modle', NAMESPACED) == \
        '~lens/modle is not a parameter; did you mean ~lens/model?'
    assert unknown_param_message('lens', NAMESPACED) == \
        '~lens is a namespace, not a parameter: it holds ~lens/model, ~lens/k1'
    assert unknown_param_message('zoom', NAMESPACED, 'camera/') == \
        'camera/zoom is not a parameter'
    many = tuple(Param('n/p%d' % index, 0, 'd') for index in range(5))
    assert unknown_param_message('n', many) == \
        '~n is a namespace, not a parameter: it holds ~n/p0, ~n/p1, ~n/p2, ... (5 in all)'



def test_parameters_set_but_not_read_are_a_warning_naming_each():
    unread = unread_params(NAMESPACED, ['seed', 'lens/k1', 'kelvin', 'kelvin', 'lens/zoom'])
    assert unread == [('kelvin', '~kelvin is not a parameter; did you mean ~light/kelvin?'),
                      ('lens/zoom', '~lens/zoom is not a parameter')]
    health = unread_health(unread)
    assert (health.level, health.message) == (WARN, 'not read: ~kelvin, ~lens/zoom')
    assert health.values == (('~kelvin', unread[0][1]), ('~lens/zoom', unread[1][1]))
    assert unread_health(unread_params(NAMESPACED, ['seed', 'lens/model'])).level == OK


def test_the_reference_tables_are_the_top_then_each_namespace():
    groups = by_namespace(NAMESPACED + (Param('rate', 1.0, 'rate (Hz)'),))
    assert [(namespace, [spec.name for spec in group]) for namespace, group in groups] == [
        ('', ['seed', 'rate']), ('lens', ['lens/model', 'lens/k1']), ('light', ['light/kelvin'])]
    assert '| `~lens/k1` | float | `-1.0` | -1.0 .. 1.0 |' in markdown_table(NAMESPACED)
    assert unit_of(NAMESPACED[3]) == 'K' and NAMESPACED[1].namespace == 'lens'
