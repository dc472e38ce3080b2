"""Which of numpy's wide (AVX-512) SIMD kernels a process can be started without, and the
environment that does it.

numpy picks its float64 sin, cos, exp... kernels at import by the CPU's features; the AVX-512
kernels round some last bits differently from the AVX2 ones, so a result that depends on those
bits differs between machines with and without AVX-512. numpy reads
``NPY_DISABLE_CPU_FEATURES`` at import: a process started with the wide features listed there
runs the kernels an AVX2-only machine runs. numpy 1.24 warns (RuntimeWarning at import) about a
listed feature the CPU lacks or its build does not dispatch, and refuses to import with one of
its baseline features listed, so only the features that can really be turned off are listed.
"""
from typing import Dict, List, Mapping, Sequence

DISABLE_VARIABLE = 'NPY_DISABLE_CPU_FEATURES'
WIDE_KERNEL_FEATURES = ('AVX512F', 'AVX512CD', 'AVX512_SKX', 'AVX512_CLX', 'AVX512_CNL',
                        'AVX512_ICL')
"""numpy's names of the AVX-512 feature groups it dispatches kernels for on x86-64."""
NOTHING_TO_DISABLE = 'no wide kernels to disable'


def features_to_disable(present: Mapping[str, bool], baseline: Sequence[str],
                        dispatched: Sequence[str],
                        wide: Sequence[str] = WIDE_KERNEL_FEATURES) -> List[str]:
    """The ``wide`` features numpy can turn off in this process, in ``wide``'s order: on the
    CPU (``present``, numpy's ``__cpu_features__``), among the features its build dispatches at
    run time (``dispatched``) and not compiled in unconditionally (``baseline``)."""
    return [feature for feature in wide
            if present.get(feature) and feature in dispatched and feature not in baseline]


def numpy_features_to_disable() -> List[str]:
    """:func:`features_to_disable` for this process's numpy and CPU (a process started with
    some of them already disabled lists only the rest)."""
    from numpy.core import _multiarray_umath as umath
    return features_to_disable(umath.__cpu_features__, umath.__cpu_baseline__,
                               umath.__cpu_dispatch__)


def narrow_kernel_environment(features: Sequence[str]) -> Dict[str, str]:
    """The environment variables that start a process without ``features`` (none when there
    is nothing to disable)."""
    return {DISABLE_VARIABLE: ' '.join(features)} if features else {}


def describe(features: Sequence[str]) -> str:
    """One phrase for a report: the variable as set, or :data:`NOTHING_TO_DISABLE`."""
    return '%s="%s"' % (DISABLE_VARIABLE, ' '.join(features)) if features else NOTHING_TO_DISABLE
