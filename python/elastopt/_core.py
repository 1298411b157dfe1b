"""The process-wide context, errors and small helpers shared by the modules."""
from __future__ import annotations

import json
import logging
import os
from typing import Any, Dict, Iterable, List, Mapping, Optional, Tuple, Union

from ._ffi import ffi, lib, string

log = logging.getLogger("elastopt")


#: scene / solver overrides: a dict {"time.steps": 20, ...} or "key=value" strings (the CLI's -o)
Overrides = Union[Mapping[str, Any], Iterable[str], str, None]


class ElastoptError(Exception):
    """An error returned by the C library: `status` (negative eo_status), `name`
    ("EO_ERR_PARSE") and `message` (the context's message: file, line, element);
    str(error) is "message [name]"."""

    status: int
    name: str
    message: str

    def __init__(self, status: int, message: str) -> None:
        self.status = status
        self.name = string(lib.eo_status_name(status))
        self.message = message
        super().__init__(f"{message} [{self.name}]" if message else self.name)


# One context for the whole process: registries are process-wide anyway (registry.h),
# and an optimizer registered from Python must outlive every solver that uses it.
_ctx_p = ffi.new("eo_ctx **")
if lib.eo_ctx_create(ffi.NULL, _ctx_p) < 0:
    raise MemoryError("elastopt: cannot create a context")
ctx = _ctx_p[0]

_LEVELS = {0: logging.ERROR, 1: logging.WARNING, 2: logging.INFO, 3: logging.DEBUG}


@ffi.callback("void(int, const char *, void *)")
def _logger(level, msg, user):
    log.log(_LEVELS.get(level, logging.INFO), "%s", string(msg))


lib.eo_ctx_set_logger(ctx, _logger, ffi.NULL, 2)

# An exception raised inside a Python callback called from C (optimizer, progress): kept
# here while C unwinds with an error status, re-raised by check().
_pending = []


def set_pending(exc: BaseException) -> None:
    """Keep an exception raised in a callback called from C; check() re-raises it."""
    _pending.append(exc)


def check(rc: int) -> int:
    """Raise for a negative status (the pending Python exception of a callback first)."""
    if _pending:
        exc = _pending.pop()
        _pending.clear()
        lib.eo_ctx_clear_error(ctx)
        raise exc
    if rc < 0:
        msg = string(lib.eo_ctx_message(ctx))
        lib.eo_ctx_clear_error(ctx)
        raise ElastoptError(rc, msg)
    return rc


def c_error(status: int, text: str, in_ctx: Any = None) -> int:
    """Record an error message in a context (default the package's; from a callback:
    the one the C caller reads) and return status."""
    loc = ffi.new("eo_errloc *", {"file": ffi.NULL, "line": -1, "column": -1,
                                  "kind": ffi.NULL, "index": -1})
    return lib.eo_error_at(ctx if in_ctx is None else in_ctx, status, loc[0], b"%s",
                           ffi.new("char[]", text.encode()))


def take_json(j: Any) -> Any:
    """A new json_t reference to a Python object (the reference is released)."""
    if j == ffi.NULL:
        raise MemoryError("elastopt: JSON echo failed")
    try:
        s = lib.json_dumps(j, 0)
        try:
            return json.loads(ffi.string(s).decode())
        finally:
            lib.free(s)
    finally:
        lib.json_delete(j)


def override_text(key: str, value: Any) -> str:
    """`key=value` of an -o override: strings as they are (the CLI's rule: JSON if it
    parses as JSON, else a string), everything else as JSON."""
    if isinstance(value, str):
        return f"{key}={value}"
    return f"{key}={json.dumps(value)}"


def overrides_list(overrides: Overrides) -> List[str]:
    """A dict {key: value} or an iterable of "key=value" strings -> list of str."""
    if overrides is None:
        return []
    if isinstance(overrides, dict):
        return [override_text(k, v) for k, v in overrides.items()]
    if isinstance(overrides, str):
        return [overrides]
    return list(overrides)


def reason_name(r: int) -> str:
    """The name of an eo_reason value ("converged_decrement", "diverged_max_iters", ...)."""
    return string(lib.eo_reason_name(r))


def live_bytes() -> int:
    """Bytes allocated through the package's context and not yet freed."""
    return lib.eo_ctx_live_bytes(ctx)


def abi_version() -> int:
    """The library's ABI version (plugin.h EO_ABI_VERSION)."""
    return lib.eo_abi_version()


def methods(kind: Optional[str] = None) -> Union[Dict[str, List[Tuple[str, str]]], List[Tuple[str, str]]]:
    """Registered methods: {kind: [(name, summary), ...]} or the list of one kind
    ("optimizer", "hessian_fix", "linesearch", "stop", "linear", "material",
    "integrator", "scene", "element", "term")."""
    from ._ffi import KINDS
    out = {}
    for k, key in enumerate(KINDS):
        if kind is not None and key != kind:
            continue
        arr = lib.eo_registry_list(k)
        items = []
        i = 0
        while arr != ffi.NULL and arr[i] != ffi.NULL:
            mi = ffi.cast("const eo_method_info *", arr[i])
            items.append((string(mi.name), string(mi.summary)))
            i += 1
        out[key] = items
    if kind is not None:
        if kind not in out:
            raise ValueError(f"unknown kind {kind!r}; valid: {', '.join(KINDS)}")
        return out[kind]
    return out


def load_plugin(path: Union[str, "os.PathLike[str]"]) -> None:
    """Load a plug-in shared object (plugin.h) into this process's registries;
    ElastoptError with the library's message if it cannot."""
    check(lib.eo_plugin_load(ctx, str(path).encode()))
