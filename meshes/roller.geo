// roller.geo -- a cylinder pressed between two plates (Q4 only), the half
// x >= 0 of a scene symmetric about x = 0 and about y = 0:
//   roller: half disk of radius 1 centred at the origin (x >= 0); its upper
//           arc touches the upper plate at (0, 1), its lower arc the lower
//           plate at (0, -1);
//   upper:  [0,4]x[1,5];   lower: [0,4]x[-5,-1].
// Separate, disconnected meshes; sizes graded from the two contact points as
// in hertz.geo (s = 2^-level: every level halves the sizes), the roller
// `ratio` times the plates' (non-matching contact meshes). The size field is
// the same above and below y = 0; gmsh's meshes of the two halves are close
// to mirror images, not exactly.
//   gmsh -2 -format msh41 -setnumber level 1 roller.geo -o roller_1.msh
DefineConstant[
  level   = {1,     Min -2, Max 6, Step 1, Name "Parameters/level"},
  h0      = {0.025, Name "Parameters/h0"},
  ratio   = {0.7,   Name "Parameters/ratio"},
  grading = {0.25,  Name "Parameters/grading"},
  hmax    = {0.8,   Name "Parameters/hmax"},
  rfine   = {0.2,   Name "Parameters/rfine"}
];

Mesh.SaveAll = 0;
Mesh.ElementOrder = 1;
Mesh.Algorithm = 6;               // Frontal-Delaunay (8 segfaults in gmsh 4.8.4)
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 1;  // Blossom
Mesh.SubdivisionAlgorithm = 1;    // all-quad
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

s = 2 / 2^level;

// ---------------- roller ----------------
Point(1) = {0, 0, 0};    // centre
Point(2) = {0, 1, 0};    // upper contact point
Point(3) = {1, 0, 0};
Point(4) = {0, -1, 0};   // lower contact point
Circle(1) = {3, 1, 2};   // upper arc
Line(2) = {2, 4};        // axis
Circle(3) = {4, 1, 3};   // lower arc
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};

// ---------------- upper plate ----------------
Point(11) = {0, 1, 0};
Point(12) = {4, 1, 0};
Point(13) = {4, 5, 0};
Point(14) = {0, 5, 0};
Line(11) = {11, 12};     // bottom (contact)
Line(12) = {12, 13};
Line(13) = {13, 14};     // top (load)
Line(14) = {14, 11};     // axis
Curve Loop(2) = {11, 12, 13, 14};
Plane Surface(2) = {2};

// ---------------- lower plate ----------------
Point(21) = {0, -1, 0};
Point(22) = {0, -5, 0};
Point(23) = {4, -5, 0};
Point(24) = {4, -1, 0};
Line(21) = {21, 22};     // axis
Line(22) = {22, 23};     // bottom (fixed)
Line(23) = {23, 24};
Line(24) = {24, 21};     // top (contact)
Curve Loop(3) = {21, 22, 23, 24};
Plane Surface(3) = {3};

// ---------------- size fields ----------------
Field[1] = Distance;
Field[1].PointsList = {11, 21};
Field[2] = Threshold;           // plate size
Field[2].InField = 1;
Field[2].SizeMin = s * h0;
Field[2].SizeMax = s * hmax;
Field[2].DistMin = rfine;
Field[2].DistMax = rfine + (hmax - h0) / grading;
Field[3] = MathEval;            // roller size
Field[3].F = Sprintf("%.17g * F2", ratio);
Field[4] = Restrict;
Field[4].InField = 3;
Field[4].SurfacesList = {1};
Field[4].CurvesList = {1, 2, 3};
Field[4].PointsList = {1, 2, 3, 4};
Field[5] = Restrict;
Field[5].InField = 2;
Field[5].SurfacesList = {2, 3};
Field[5].CurvesList = {11, 12, 13, 14, 21, 22, 23, 24};
Field[5].PointsList = {11, 12, 13, 14, 21, 22, 23, 24};
Field[6] = Min;
Field[6].FieldsList = {4, 5};
Background Field = 6;

// ---------------- physical groups ----------------
Physical Surface("roller", 1) = {1};
Physical Curve("roller_top", 11) = {1};
Physical Curve("roller_axis", 12) = {2};
Physical Curve("roller_bottom", 13) = {3};
Physical Surface("upper", 2) = {2};
Physical Curve("upper_bottom", 21) = {11};
Physical Curve("upper_top", 23) = {13};
Physical Curve("upper_axis", 24) = {14};
Physical Surface("lower", 3) = {3};
Physical Curve("lower_axis", 31) = {21};
Physical Curve("lower_bottom", 32) = {22};
Physical Curve("lower_top", 34) = {24};
