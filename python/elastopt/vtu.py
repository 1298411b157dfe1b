"""Read the VTU frames `elastopt run` writes (VTK XML unstructured grid, appended raw
data with UInt64 headers, lib/mesh/vtu.c), e.g. to compare a CLI run with a Python one."""
from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any, Dict, Union

import numpy as np

_TYPES = {"Float64": np.float64, "Int64": np.int64, "UInt8": np.uint8, "Int32": np.int32,
          "Float32": np.float32, "UInt64": np.uint64}
_ARRAY = re.compile(rb'<DataArray type="(\w+)" Name="(\w+)"(?: NumberOfComponents="(\d+)")?'
                    rb' format="appended" offset="(\d+)"/>')


def read_vtu(path: Union[str, "os.PathLike[str]"]) -> Dict[str, Any]:
    """{"points": nv x 3, "point_data": {name: array}, "cell_data": {name: array},
    "cells": connectivity (nt x 4)} of one frame."""
    raw = Path(path).read_bytes()
    mark = raw.index(b'<AppendedData encoding="raw">')
    start = raw.index(b"_", mark) + 1
    head = raw[:mark]
    pd_span = re.search(rb"<PointData>(.*?)</PointData>", head, re.S)
    cd_span = re.search(rb"<CellData>(.*?)</CellData>", head, re.S)
    out = {"point_data": {}, "cell_data": {}}
    for m in _ARRAY.finditer(head):
        typ, name, ncomp, off = m.group(1).decode(), m.group(2).decode(), m.group(3), int(m.group(4))
        nbytes = int(np.frombuffer(raw, dtype="<u8", count=1, offset=start + off)[0])
        dt = np.dtype(_TYPES[typ]).newbyteorder("<")
        a = np.frombuffer(raw, dtype=dt, count=nbytes // dt.itemsize, offset=start + off + 8).copy()
        if ncomp:
            a = a.reshape(-1, int(ncomp))
        where = m.start()
        if pd_span and pd_span.start(1) <= where < pd_span.end(1):
            out["point_data"][name] = a
        elif cd_span and cd_span.start(1) <= where < cd_span.end(1):
            out["cell_data"][name] = a
        elif name == "Points":
            out["points"] = a
        elif name == "connectivity":
            out["cells"] = a.reshape(-1, 4)
    return out
