"""Which wide numpy kernels a process is started without: only the AVX-512 features the CPU
has, numpy dispatches and are not its baseline (numpy warns about the others, or refuses to
import), and no variable at all when none is left."""
import json
import os
import subprocess
import sys

from can_seeker.evaluation.cpu_features import (DISABLE_VARIABLE, NOTHING_TO_DISABLE,
                                                WIDE_KERNEL_FEATURES, describe,
                                                features_to_disable,
                                                narrow_kernel_environment,
                                                numpy_features_to_disable)

DISPATCHED = ('SSSE3', 'SSE41', 'POPCNT', 'SSE42', 'AVX', 'F16C', 'FMA3', 'AVX2', 'AVX512F',
              'AVX512CD', 'AVX512_SKX', 'AVX512_CLX', 'AVX512_CNL', 'AVX512_ICL')
BASELINE = ('SSE', 'SSE2', 'SSE3')
AVX2_ONLY = {'SSE': True, 'SSE2': True, 'SSE3': True, 'AVX': True, 'FMA3': True, 'AVX2': True,
             'AVX512F': False, 'AVX512CD': False, 'AVX512_SKX': False, 'AVX512_CLX': False,
             'AVX512_CNL': False, 'AVX512_ICL': False}
SKYLAKE_SERVER = dict(AVX2_ONLY, AVX512F=True, AVX512CD=True, AVX512_SKX=True)


def test_an_ice_lake_cpu_disables_every_wide_feature():
    present = dict(AVX2_ONLY, **{feature: True for feature in WIDE_KERNEL_FEATURES})
    assert features_to_disable(present, BASELINE, DISPATCHED) == list(WIDE_KERNEL_FEATURES)


def test_only_the_features_the_cpu_has_are_listed():
    assert features_to_disable(SKYLAKE_SERVER, BASELINE, DISPATCHED) == [
        'AVX512F', 'AVX512CD', 'AVX512_SKX']


def test_an_avx2_only_cpu_has_nothing_to_disable_and_sets_no_variable():
    features = features_to_disable(AVX2_ONLY, BASELINE, DISPATCHED)
    assert features == []
    assert narrow_kernel_environment(features) == {}
    assert describe(features) == NOTHING_TO_DISABLE


def test_features_the_build_does_not_dispatch_or_has_as_baseline_are_not_listed():
    dispatched = [feature for feature in DISPATCHED if feature != 'AVX512_CNL']
    baseline = BASELINE + ('AVX512F',)
    present = dict(AVX2_ONLY, **{feature: True for feature in WIDE_KERNEL_FEATURES})
    assert features_to_disable(present, baseline, dispatched) == [
        'AVX512CD', 'AVX512_SKX', 'AVX512_CLX', 'AVX512_ICL']


def test_the_environment_lists_the_features_separated_by_spaces():
    features = ['AVX512F', 'AVX512CD']
    assert narrow_kernel_environment(features) == {DISABLE_VARIABLE: 'AVX512F AVX512CD'}
    assert describe(features) == 'NPY_DISABLE_CPU_FEATURES="AVX512F AVX512CD"'


def test_this_process_lists_only_wide_features_its_numpy_reports_present():
    from numpy.core import _multiarray_umath as umath
    features = numpy_features_to_disable()
    assert set(features) <= set(WIDE_KERNEL_FEATURES)
    assert all(umath.__cpu_features__[feature] for feature in features)


def test_a_process_started_with_the_environment_runs_without_them_and_numpy_says_nothing():
    features = numpy_features_to_disable()
    probe = ('import json; from numpy.core import _multiarray_umath as umath; '
             'print(json.dumps(umath.__cpu_features__))')
    child = subprocess.run(
        [sys.executable, '-W', 'error', '-c', probe], capture_output=True, text=True,
        env=dict(os.environ, **narrow_kernel_environment(features)), check=True)
    assert child.stderr == ''
    child_features = json.loads(child.stdout)
    assert not any(child_features[feature] for feature in features)
    assert features_to_disable(child_features, BASELINE, DISPATCHED) == []
