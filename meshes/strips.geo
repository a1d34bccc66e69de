// strips.geo -- two long strips pressed together (Q4 only): the contact
// search's benchmark (tools/contact_search.py).
//   lower strip [0,L]x[-t,0], nl x ny quads;  upper strip [0,Lu]x[0,t], nu x ny quads
// (nl != nu: the interface meshes do not match; Lu < L leaves the lower
// strip's end uncovered). Loads and supports as in S2: the lower bottom on
// rollers, lower_origin pinned in x, upper_left in x, a pressure on the upper top.
//   gmsh -2 -format msh41 -setnumber nl 14000 -setnumber nu 20000 strips.geo -o strips.msh
DefineConstant[
  L  = {100,  Name "Parameters/L"},
  Lu = {100,  Name "Parameters/Lu"},
  t  = {1,    Name "Parameters/t"},
  nl = {1400, Min 1, Step 1, Name "Parameters/nl"},
  nu = {2000, Min 1, Step 1, Name "Parameters/nu"},
  ny = {1,    Min 1, Step 1, Name "Parameters/ny"}
];

Mesh.SaveAll = 0;
Mesh.RecombineAll = 1;
Mesh.ElementOrder = 1;

Point(1) = {0, -t, 0};  Point(2) = {L, -t, 0};  Point(3) = {L, 0, 0};  Point(4) = {0, 0, 0};
Line(1) = {1, 2};  Line(2) = {2, 3};  Line(3) = {3, 4};  Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = nl + 1;
Transfinite Curve{2, 4} = ny + 1;
Transfinite Surface{1} = {1, 2, 3, 4};

Point(11) = {0, 0, 0};  Point(12) = {Lu, 0, 0};  Point(13) = {Lu, t, 0};  Point(14) = {0, t, 0};
Line(11) = {11, 12};  Line(12) = {12, 13};  Line(13) = {13, 14};  Line(14) = {14, 11};
Curve Loop(2) = {11, 12, 13, 14};
Plane Surface(2) = {2};
Transfinite Curve{11, 13} = nu + 1;
Transfinite Curve{12, 14} = ny + 1;
Transfinite Surface{2} = {11, 12, 13, 14};
Recombine Surface{1, 2};

Physical Surface("lower", 1) = {1};
Physical Surface("upper", 2) = {2};
Physical Curve("lower_bottom", 11) = {1};
Physical Curve("lower_top", 13) = {3};
Physical Curve("upper_bottom", 21) = {11};
Physical Curve("upper_top", 23) = {13};
Physical Curve("upper_left", 24) = {14};
Physical Point("lower_origin", 31) = {1};
