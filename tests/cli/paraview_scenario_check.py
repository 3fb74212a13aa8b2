"""ParaView (pvpython) reads the frames of a `bushel run` of scenarios/cup-pour.yaml: the
last frame holds every element of the particles the summary counts (5-sphere clumps), with
the arrays users colour by, ids and types as integers, and the types' names."""
import json
import sys

from paraview import servermanager
from paraview.simple import PVDReader

out = sys.argv[1]
summary = json.load(open(out + "/summary.json"))
particles = PVDReader(FileName=out + "/frames/particles.pvd")
times = list(particles.TimestepValues)
assert abs(times[-1] - summary["simulated_time_s"]) < 1e-9, (times[-1], summary["simulated_time_s"])
particles.UpdatePipeline(times[-1])
p = servermanager.Fetch(particles)
assert p.GetNumberOfPoints() == 5 * summary["final"]["particles"], (p.GetNumberOfPoints(), summary["final"]["particles"])
names = {p.GetPointData().GetArrayName(i) for i in range(p.GetPointData().GetNumberOfArrays())}
assert {"radius_m", "velocity_m_s", "body_id", "type", "orientation_wxyz"} <= names, names
types = p.GetPointData().GetArray("type")
assert types.GetRange() == (0.0, 2.0), types.GetRange()  # large, medium and small
assert types.GetDataTypeAsString() == "int", types.GetDataTypeAsString()
assert p.GetPointData().GetArray("body_id").GetDataTypeAsString() == "unsigned int"
names = p.GetFieldData().GetAbstractArray("type_names")
assert [names.GetValue(i) for i in range(names.GetNumberOfValues())] == ["large", "medium", "small"]
print("paraview read", len(times), "frames; the last has", p.GetNumberOfPoints(), "elements")
