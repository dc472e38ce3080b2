"""calibrate_colour end to end on the recorded bags of test/data: the thresholds it writes
find the can in the bag as the defaults do, for both colour models, and load as parameters."""
import pathlib

import pytest
import yaml

from can_seeker.tools.calibrate_colour import main as calibrate_colour
from can_seeker.tools.bag_detect import main as bag_detect

DATA = pathlib.Path(__file__).resolve().parents[1] / 'data'
BAGS = ['sim_can_320x240.bag', 'sim_crimson_can_320x240.bag', 'sim_realistic_can_320x240.bag']


def found_frames(bag, csv_path, params):
    bag_detect([str(bag), '--csv', str(csv_path)] +
               sum((['--param', '%s=%s' % item] for item in params.items()), []))
    rows = csv_path.read_text().splitlines()[1:]
    return {row.split(',')[0] for row in rows if row.split(',')[1] == '1'}


@pytest.mark.parametrize('model', ['chromaticity', 'hsv'])
@pytest.mark.parametrize('bag', BAGS)
def test_calibrated_thresholds_find_the_can_of_the_bag(tmp_path, bag, model):
    output = tmp_path / 'can.yaml'
    calibrate_colour(['--bag', str(DATA / bag), '--colour-model', model, '--output',
                      str(output)])
    values = yaml.safe_load(output.read_text())
    assert values['colour_model'] == model
    assert output.read_text().startswith('# calibrate_colour: ')
    default = found_frames(DATA / bag, tmp_path / 'default.csv', {'colour_model': model})
    calibrated = found_frames(DATA / bag, tmp_path / 'calibrated.csv', values)
    assert len(default) >= 20
    assert len(calibrated & default) >= len(default) - 1
    assert len(calibrated - default) <= 1


def test_a_box_with_no_can_is_refused(tmp_path):
    with pytest.raises(SystemExit, match='can pixels'):
        calibrate_colour(['--bag', str(DATA / BAGS[0]), '--box', '0,0,40,20', '--frames', '3'])
