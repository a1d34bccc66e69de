"""-help documents the program: every option with its default."""
from m2d import check, run

rc, out, err = run(["-help", "-bodies", "lower,upper"])
text = out + err
for opt, default in [("-mesh", ""), ("-bodies", ""), ("-plane", "strain"), ("-dirichlet", ""), ("-pressure", ""),
                     ("-traction", ""), ("-exact", "none"), ("-output_dir", "output"), ("-output_name", "solution"),
                     ("-summary", ""), ("-lower_E", "1."), ("-lower_nu", "0.3"), ("-upper_E", "1."), ("-ksp_type", ""),
                     ("-kkt_path", "condensed"), ("-kkt_ordering", "metis"), ("-kkt_ldlt", "TRUE"),
                     ("-mat_mumps_icntl_14", "20"), ("-mesh_partitioner", "metis"), ("-mesh_check", "FALSE")]:
    line = next((l for l in text.splitlines() if l.strip().startswith((opt + " ", opt + ":"))), None)
    ok = line is not None and (("<now " + default) in line or ("<" + default) in line or "default:" in line)
    check(ok, "%s documented with default '%s': %s" % (opt, default, (line or "").strip()[:100]))
