"""ParaView frames as numpy arrays: VTK XML unstructured grids (.vtu) as bushel writes them
(ASCII, or binary appended data compressed by zlib or not) and collections (.pvd).

    frame = bushel.read_vtu("runs/cup/frames/particles_00010.vtu")
    frame.points            # (n, 3) float64 [m]
    frame.point_data["radius_m"], frame.point_data["body_id"]   # numpy arrays
    frame.field_data["type_names"]                               # list of str
"""
import os
import struct
import xml.etree.ElementTree as ET
import zlib
from dataclasses import dataclass, field

import numpy as np

_TYPES = {"Float64": np.float64, "Float32": np.float32, "Int64": np.int64, "Int32": np.int32,
          "UInt64": np.uint64, "UInt32": np.uint32, "Int8": np.int8, "UInt8": np.uint8}


@dataclass
class Frame:
    """One .vtu file: points, cells and the fields over them."""
    points: np.ndarray                                # (n, 3) [m]
    connectivity: np.ndarray                          # point indices of the cells, one after another
    offsets: np.ndarray                               # per cell, the end of its indices
    cell_types: np.ndarray                            # VTK cell types (1 vertex, 3 line, 5 triangle)
    point_data: dict = field(default_factory=dict)    # name -> (n,) or (n, components)
    cell_data: dict = field(default_factory=dict)     # name -> (cells,) or (cells, components)
    field_data: dict = field(default_factory=dict)    # name -> list of str

    def cells(self):
        """The point indices of each cell, as a list of arrays."""
        starts = np.concatenate(([0], self.offsets[:-1]))
        return [self.connectivity[a:b] for a, b in zip(starts, self.offsets)]


def _header_words(root):
    return np.uint64 if root.get("header_type", "UInt32") == "UInt64" else np.uint32


def _appended_bytes(raw, at, root):
    """The bytes of one appended array starting at `at`: VTK's block header, then the blocks."""
    word = _header_words(root)
    size = np.dtype(word).itemsize
    if root.get("compressor") is None:
        (n,) = np.frombuffer(raw, word, 1, at)
        return raw[at + size:at + size + int(n)]
    if root.get("compressor") != "vtkZLibDataCompressor":
        raise ValueError(f"unsupported compressor {root.get('compressor')}")
    blocks, block, last = (int(v) for v in np.frombuffer(raw, word, 3, at))
    sizes = np.frombuffer(raw, word, blocks, at + 3 * size).astype(np.int64)
    pos = at + (3 + blocks) * size
    out = []
    for k, c in enumerate(sizes):
        data = zlib.decompress(raw[pos:pos + c])
        expected = last if (k == blocks - 1 and last) else block
        if len(data) != expected:
            raise ValueError(f"block {k} inflates to {len(data)} bytes, expected {expected}")
        out.append(data)
        pos += c
    return b"".join(out)


def _array(element, root, appended):
    kind = element.get("type")
    components = int(element.get("NumberOfComponents", "1"))
    if kind == "String":  # character codes, each string ended by a 0 (ASCII only)
        codes = bytes(int(v) for v in (element.text or "").split())
        return [s.decode() for s in codes.split(b"\0")[:-1]]
    dtype = _TYPES[kind]
    fmt = element.get("format")
    if fmt == "ascii":
        values = np.array((element.text or "").split(), dtype=np.float64).astype(dtype)
    elif fmt == "appended":
        values = np.frombuffer(_appended_bytes(appended, int(element.get("offset")), root), dtype=dtype)
    else:
        raise ValueError(f"unsupported DataArray format {fmt}")
    return values.reshape(-1, components) if components > 1 else values


def read_vtu(path):
    """A .vtu file (ASCII, or raw appended data, zlib-compressed or not) as a Frame."""
    raw = open(path, "rb").read()
    # The appended data is not XML: cut it out, and parse what is around it.
    start = raw.find(b"<AppendedData")
    appended = b""
    if start >= 0:
        data = raw.index(b"_", raw.index(b">", start)) + 1
        end = raw.rindex(b"</AppendedData>")
        appended = raw[data:end]
        raw = raw[:start] + raw[end + len(b"</AppendedData>"):]
    root = ET.fromstring(raw)
    if root.get("byte_order", "LittleEndian") != "LittleEndian":
        raise ValueError(f"{path}: big-endian files are not read")
    grid = root.find("UnstructuredGrid")
    piece = grid.find("Piece")
    read = lambda e: _array(e, root, appended)  # noqa: E731
    named = lambda section: {e.get("Name"): read(e) for e in section} if section is not None else {}  # noqa: E731
    cells = {e.get("Name"): read(e) for e in piece.find("Cells")}
    points = read(piece.find("Points").find("DataArray"))
    return Frame(points=np.asarray(points).reshape(-1, 3), connectivity=cells["connectivity"],
                 offsets=cells["offsets"], cell_types=cells["types"],
                 point_data=named(piece.find("PointData")), cell_data=named(piece.find("CellData")),
                 field_data=named(grid.find("FieldData")))


def read_pvd(path):
    """A .pvd collection: a list of (time [s], path of the .vtu file)."""
    folder = os.path.dirname(path)
    return [(float(d.get("timestep")), os.path.join(folder, d.get("file")))
            for d in ET.parse(path).getroot().find("Collection")]
