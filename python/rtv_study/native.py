"""The project's native code in-process: rt-vehicle's study runs (src/studies/study_run.rs) through the
`rtv-study-native` library (crates/study-native), one C function with JSON in and out, called by ctypes.

The library is found at $RTV_STUDY_NATIVE, else beside this package in the repository's
target/release/ (`cargo build --release -p rtv-study-native`). A Dask worker on another machine gets it from
the client (runner.NativeLibrary), so workers need only Python and this package.
"""
import ctypes
import json
import os
from pathlib import Path

LIBRARY_NAME = "librtv_study_native.so"
_library = None
_library_path = None


class NativeError(Exception):
    """A run the model refused or could not finish: `cause` is the model's cause (Input, Data,
    StepSizeInstability, PhysicalEvent, …), the message says why, and `field`, where the refusal is about one
    field of the request, is that field's JSON Pointer (`/metrics/2`, `/parameters/road_friction`, `/case`),
    else None."""

    def __init__(self, cause, message, field=None):
        super().__init__(message)
        self.cause = cause
        self.message = message
        self.field = field


def default_library_path():
    if os.environ.get("RTV_STUDY_NATIVE"):
        return Path(os.environ["RTV_STUDY_NATIVE"])
    return Path(__file__).resolve().parents[2] / "target" / "release" / LIBRARY_NAME


def load(path=None):
    """Load the library (once per process; a second path is refused rather than silently ignored)."""
    global _library, _library_path
    path = Path(path) if path else default_library_path()
    if _library is not None:
        if path.resolve() != _library_path.resolve():
            raise RuntimeError(f"the study library is already loaded from {_library_path}, not {path}")
        return _library
    if not path.is_file():
        raise FileNotFoundError(
            f"{path}: the study library is missing: build it with `cargo build --release -p rtv-study-native` "
            "or set RTV_STUDY_NATIVE to its path")
    lib = ctypes.CDLL(str(path))
    lib.rtv_study_call.restype = ctypes.c_void_p
    lib.rtv_study_call.argtypes = [ctypes.c_char_p]
    lib.rtv_study_free.argtypes = [ctypes.c_void_p]
    lib.rtv_study_free.restype = None
    _library, _library_path = lib, path
    return lib


def call(op, request=None, library=None):
    """One call: the answer's "ok" value, or NativeError."""
    lib = load(library)
    answer = lib.rtv_study_call(json.dumps({"op": op, "request": request}).encode())
    try:
        text = ctypes.string_at(answer).decode()
    finally:
        lib.rtv_study_free(answer)
    reply = json.loads(text)
    if "error" in reply:
        error = reply["error"]
        raise NativeError(error["cause"], error["message"], error.get("field"))
    return reply["ok"]


def describe(library=None):
    """The cases, their metrics, the statistics, the outputs and the FMU parameters (with ranges)."""
    return call("describe", library=library)
