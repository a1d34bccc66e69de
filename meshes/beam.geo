// beam.geo -- a cantilever [0,L]x[0,t], nx x ny structured quads (Q4), for the
// thin-body checks (docs/trust.md): clamped on beam_left, loaded on beam_right.
//   gmsh -2 -format msh41 -setnumber nx 1000 -setnumber ny 4 beam.geo -o beam.msh
DefineConstant[
  L  = {10,   Name "Parameters/L"},
  t  = {0.01, Name "Parameters/t"},
  nx = {1000, Min 1, Step 1, Name "Parameters/nx"},
  ny = {1,    Min 1, Step 1, Name "Parameters/ny"}
];

Mesh.SaveAll = 0;
Mesh.RecombineAll = 1;
Mesh.ElementOrder = 1;

Point(1) = {0, 0, 0};
Point(2) = {L, 0, 0};
Point(3) = {L, t, 0};
Point(4) = {0, t, 0};
Line(1) = {1, 2};   // bottom y=0
Line(2) = {2, 3};   // right  x=L
Line(3) = {3, 4};   // top    y=t
Line(4) = {4, 1};   // left   x=0
Curve Loop(1) = {1, 2, 3, 4};   // counter-clockwise
Plane Surface(1) = {1};

Transfinite Curve{1, 3} = nx + 1;
Transfinite Curve{2, 4} = ny + 1;
Transfinite Surface{1} = {1, 2, 3, 4};
Recombine Surface{1};

Physical Surface("beam", 1) = {1};
Physical Curve("beam_bottom", 11) = {1};
Physical Curve("beam_right", 12) = {2};
Physical Curve("beam_top", 13) = {3};
Physical Curve("beam_left", 14) = {4};
