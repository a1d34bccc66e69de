// hertz_two.geo -- Hertz contact of two elastic cylinders (Q4 only), for
// -hertz_radius R1:R2 (effective radius R = R1 R2 / (R1 + R2)).
//   upper: quarter disk of radius R1 centred at (0,R1), x in [0,R1], loaded on
//          its flat top y = R1;
//   lower: quarter disk of radius R2 centred at (0,-R2), x in [0,R2], held on
//          its flat bottom y = -R2; they touch at the origin.
// Sizes as in hertz.geo (fine near the origin, growing with the distance).
//   gmsh -2 -format msh41 -setnumber level 1 hertz_two.geo -o hertz_two_1.msh
DefineConstant[
  level   = {0,     Min -2, Max 6, Step 1, Name "Parameters/level"},
  R1      = {1,     Name "Parameters/R1"},
  R2      = {2,     Name "Parameters/R2"},
  h0      = {0.025, Name "Parameters/h0"},
  ratio   = {0.7,   Name "Parameters/ratio"},
  grading = {0.25,  Name "Parameters/grading"},
  hmax    = {0.8,   Name "Parameters/hmax"},
  rfine   = {0.2,   Name "Parameters/rfine"}
];

Mesh.SaveAll = 0;
Mesh.ElementOrder = 1;
// NOTE: Mesh.Algorithm = 8 segfaults in the installed gmsh 4.8.4 build.
Mesh.Algorithm = 6;               // Frontal-Delaunay
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 1;  // Blossom
Mesh.SubdivisionAlgorithm = 1;    // split into quads -> guaranteed all-quad
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

s = 2 / 2^level;   // factor 2: the subdivision halves the triangle size

// ---------------- upper cylinder ----------------
Point(1) = {0, 0, 0};    // tip (contact point)
Point(2) = {R1, R1, 0};
Point(3) = {0, R1, 0};   // centre
Circle(1) = {1, 3, 2};   // arc (contact surface)
Line(2) = {2, 3};        // top, y = R1
Line(3) = {3, 1};        // axis, x = 0
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};

// ---------------- lower cylinder ----------------
Point(11) = {0, 0, 0};    // tip
Point(12) = {0, -R2, 0};  // centre
Point(13) = {R2, -R2, 0};
Line(11) = {11, 12};      // axis, x = 0
Line(12) = {12, 13};      // bottom, y = -R2
Circle(14) = {13, 12, 11}; // arc (contact surface)
Curve Loop(2) = {11, 12, 14};
Plane Surface(2) = {2};

// ---------------- size fields ----------------
Field[1] = Distance;
Field[1].PointsList = {11};
Field[2] = Threshold;           // block size
Field[2].InField = 1;
Field[2].SizeMin = s * h0;
Field[2].SizeMax = s * hmax;
Field[2].DistMin = rfine;
Field[2].DistMax = rfine + (hmax - h0) / grading;
Field[3] = MathEval;            // cylinder size
Field[3].F = Sprintf("%.17g * F2", ratio);
Field[4] = Restrict;
Field[4].InField = 3;
Field[4].SurfacesList = {1};
Field[4].CurvesList = {1, 2, 3};
Field[4].PointsList = {1, 2, 3};
Field[5] = Restrict;
Field[5].InField = 2;
Field[5].SurfacesList = {2};
Field[5].CurvesList = {11, 12, 14};
Field[5].PointsList = {11, 12, 13};
Field[6] = Min;
Field[6].FieldsList = {4, 5};
Background Field = 6;

// ---------------- physical groups ----------------
Physical Surface("upper", 1) = {1};
Physical Curve("upper_arc", 11) = {1};
Physical Curve("upper_top", 12) = {2};
Physical Curve("upper_axis", 13) = {3};
Physical Surface("lower", 2) = {2};
Physical Curve("lower_axis", 21) = {11};
Physical Curve("lower_bottom", 22) = {12};
Physical Curve("lower_arc", 24) = {14};
