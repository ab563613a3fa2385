"""Choice of MuJoCo's offscreen OpenGL backend (EGL or OSMesa), made before mujoco is imported.

MuJoCo reads MUJOCO_GL, and PyOpenGL reads PYOPENGL_PLATFORM, once, when they are first imported; so
the backend must be chosen before the first `import mujoco` of the process. `configure_gl` prefers
the requested backend, falls back to the other one when the requested one's library is missing, and
raises one clear DeviceError when neither can be loaded.
"""

import ctypes
import ctypes.util
import os
import sys

from joshua_core.models import GL_BACKENDS
from joshua_runtime.errors import DeviceError, SettingsError

DEFAULT_GL_BACKEND = GL_BACKENDS[0]

# Shared libraries each backend needs, most specific name first.
_LIBRARIES = {
    "egl": ("libEGL.so.1", "libEGL.so"),
    "osmesa": ("libOSMesa.so.8", "libOSMesa.so.6", "libOSMesa.so"),
}
# Debian packages that provide them, named in the error message.
_PACKAGES = {"egl": "libegl1 libegl-mesa0", "osmesa": "libosmesa6"}


def library_loadable(backend: str) -> bool:
    """True when the shared library the backend needs can be loaded in this process."""
    names = list(_LIBRARIES[backend])
    found = ctypes.util.find_library("EGL" if backend == "egl" else "OSMesa")
    if found:
        names.append(found)
    for name in names:
        try:
            ctypes.CDLL(name)
            return True
        except OSError:
            continue
    return False


def choose_gl_backend(requested: str = "", loadable=library_loadable) -> str:
    """The requested backend when its library loads, else the other one, else a DeviceError."""
    requested = (requested or DEFAULT_GL_BACKEND).lower()
    if requested not in GL_BACKENDS:
        raise SettingsError(f"gl_backend {requested!r} is not one of {', '.join(GL_BACKENDS)}")
    for backend in [requested] + [b for b in GL_BACKENDS if b != requested]:
        if loadable(backend):
            return backend
    raise DeviceError(
        "no offscreen OpenGL for camera rendering: neither EGL nor OSMesa can be loaded "
        f"(install the Debian packages {_PACKAGES['egl']} or {_PACKAGES['osmesa']})"
    )


def configure_gl(requested: str = "") -> str:
    """Select the offscreen backend for this process (sets MUJOCO_GL) and return its name."""
    if "mujoco" in sys.modules:
        # Too late to change: keep whatever the process already chose.
        return os.environ.get("MUJOCO_GL", "") or (requested or DEFAULT_GL_BACKEND).lower()
    backend = choose_gl_backend(requested)
    os.environ["MUJOCO_GL"] = backend
    os.environ["PYOPENGL_PLATFORM"] = backend
    return backend


def render_failure(backend: str, exc: BaseException) -> DeviceError:
    """The DeviceError reported when the chosen backend loads but cannot create a context."""
    other = next(b for b in GL_BACKENDS if b != backend)
    return DeviceError(
        f"offscreen rendering with MUJOCO_GL={backend} failed ({type(exc).__name__}: {exc}); "
        f'try simulation gl_backend "{other}" (Debian packages: {_PACKAGES[other]})'
    )
