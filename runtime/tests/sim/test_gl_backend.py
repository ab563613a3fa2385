"""Choice of the offscreen GL backend: requested first, the other as fallback, one clear error else."""

import pytest

from joshua_runtime.errors import DeviceError, SettingsError
from joshua_runtime.sim.gl_backend import choose_gl_backend, render_failure


def test_requested_backend_wins_when_it_loads():
    assert choose_gl_backend("osmesa", loadable=lambda b: True) == "osmesa"
    assert choose_gl_backend("", loadable=lambda b: True) == "egl"


def test_falls_back_to_the_other_backend():
    assert choose_gl_backend("osmesa", loadable=lambda b: b == "egl") == "egl"
    assert choose_gl_backend("egl", loadable=lambda b: b == "osmesa") == "osmesa"


def test_no_backend_is_one_device_error_naming_the_packages():
    with pytest.raises(DeviceError, match=r"neither EGL nor OSMesa can be loaded .*libegl1 libegl-mesa0 or libosmesa6"):
        choose_gl_backend("egl", loadable=lambda b: False)


def test_unknown_backend_is_a_settings_error():
    with pytest.raises(SettingsError, match=r"gl_backend 'glx' is not one of egl, osmesa"):
        choose_gl_backend("glx")


def test_render_failure_suggests_the_other_backend():
    error = render_failure("egl", RuntimeError("eglInitialize failed"))
    assert error.exit_code == 3
    assert str(error) == (
        "offscreen rendering with MUJOCO_GL=egl failed (RuntimeError: eglInitialize failed); "
        'try simulation gl_backend "osmesa" (Debian packages: libosmesa6)'
    )
