"""The same Hertz scene (level 1) in m/Pa and in mm/MPa takes the same
active-set steps and gives the same scaled answer: c is set from the material
and the mesh, and every tolerance is relative."""
from m2d import check, mesh, opts, solve

common = ["-options_file", opts("hertz"), "-mesh", mesh("hertz_1"), "-output_vtu", "0"]
si = solve("units_si", common + ["-cylinder_E", "200e9", "-block_E", "200e9", "-pressure", "cylinder_top:0.43e9"])
mm = solve("units_mm", common + ["-mesh_scale", "1000", "-hertz_radius", "1000", "-cylinder_E", "200e3", "-block_E", "200e3", "-pressure", "cylinder_top:0.43e3"])
check(si["iterations"] == mm["iterations"] and si["active_nodes"] == mm["active_nodes"], "same steps (%d, %d) and active nodes (%d, %d)" % (si["iterations"], mm["iterations"], si["active_nodes"], mm["active_nodes"]))
for key, scale in (("half_width", 1e3), ("peak_pressure", 1e-6), ("pressure_l2_rel", 1.0), ("contact_force", 1e-3)):
    a, b = si[key] * scale, mm[key]
    check(abs(a - b) <= 1e-9 * abs(b), "%s: %.10e (m, Pa, scaled) vs %.10e (mm, MPa)" % (key, a, b))
