"""thermnet: lumped-parameter thermal networks from Python.

    import thermnet
    m = thermnet.Model.load("models/aerial_camera/camera.tnet")
    r = m.simulate(case="hot", params={"h_cp": 400}, nodes=["lens1"])
    r.times, r.temperatures          # numpy arrays: s and degC
    m.calibrate(method="lm")         # the `thermnet calibrate --json` report as a dict

Errors in a model raise thermnet.ModelError (a ValueError) with .file, .line and .column.
"""

import os as _os
import sys as _sys

# Plugin libraries (`plugin "lib.so"` in a model, thermnet.load_plugin) resolve the kernel's
# symbols against the module, as they do against the `thermnet` executable: load it globally.
_flags = _sys.getdlopenflags()
_sys.setdlopenflags(_flags | _os.RTLD_GLOBAL)
try:
    from ._thermnet import Model, ModelError, Result, load_plugin, __version__  # noqa: F401
finally:
    _sys.setdlopenflags(_flags)

__all__ = ["Model", "ModelError", "Result", "load_plugin", "__version__"]
