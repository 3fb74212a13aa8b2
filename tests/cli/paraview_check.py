"""ParaView (pvpython) reads the frames `bushel demo funnel --out DIR` wrote: the particle
and geometry collections, their point and cell counts and the arrays users colour by."""
import sys

from paraview import servermanager
from paraview.simple import PVDReader

frames = sys.argv[1]
particles = PVDReader(FileName=frames + "/particles.pvd")
times = list(particles.TimestepValues)
assert len(times) >= 6 and abs(times[-1] - 0.6) < 1e-3, times
particles.UpdatePipeline(times[-1])
p = servermanager.Fetch(particles)
assert p.GetNumberOfPoints() == 150, p.GetNumberOfPoints()
names = {p.GetPointData().GetArrayName(i) for i in range(p.GetPointData().GetNumberOfArrays())}
assert {"radius_m", "velocity_m_s", "body_id", "type", "orientation_wxyz"} <= names, names
radius = p.GetPointData().GetArray("radius_m").GetRange()
assert abs(radius[0] - 1.82e-3) < 1e-9 and abs(radius[1] - 1.82e-3) < 1e-9, radius

geometry = PVDReader(FileName=frames + "/geometry.pvd")
geometry.UpdatePipeline(times[-1])
g = servermanager.Fetch(geometry)
assert g.GetNumberOfCells() == 128 + 2 + 2, g.GetNumberOfCells()  # funnel (64 x 2), gate, floor
part = g.GetCellData().GetArray("part").GetRange()
assert part == (0.0, 2.0), part
print("paraview read", len(times), "frames of", p.GetNumberOfPoints(), "particles and", g.GetNumberOfCells(), "triangles")
