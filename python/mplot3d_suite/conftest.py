"""matplotlib's mplot3d tests with plytrace.mpl on every 3-D axes: each
Axes3D is fixed (plytrace.mpl.fix) at the end of its construction, so
before its first draw. PLYTRACE_MPL_SUITE=plain leaves them unfixed (the
same run without the bridge, for comparison)."""

import os

from matplotlib.testing.conftest import (  # noqa: F401
    high_memory,
    mpl_test_settings,
    pytest_configure,
    pytest_unconfigure,
)
from mpl_toolkits.mplot3d import Axes3D

import plytrace.mpl

if os.environ.get("PLYTRACE_MPL_SUITE") != "plain":
    _init = Axes3D.__init__

    def _fixed_init(self, *args, **kwargs):
        _init(self, *args, **kwargs)
        plytrace.mpl.fix(self)

    Axes3D.__init__ = _fixed_init
