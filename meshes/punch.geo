// punch.geo -- a stiff punch with rounded corners pressed on an elastic
// foundation (half model, symmetry on x = 0; Q4 only).
//   punch:      flat bottom x in [0, b - r] at y = 0, a quarter circle of
//               radius r to the side x = b, the side up to y = H, loaded top.
//               The curvature jumps from 0 to 1/r where the corner meets the
//               bottom, and the pressure has a kink there (p' ~ log|x - x0|).
//   foundation: [0, W] x [-D, 0].
// The contact zone spans the flat bottom and ends on the rounded corner,
// where the pressure peaks; its edge is a smooth one (p ~ sqrt(distance)).
// Sizes: hc at the punch's bottom and corner and on the foundation under
// them, growing with the distance; both bodies meshed alike (balanced sides).
//   gmsh -2 -format msh41 punch.geo -o punch.msh
DefineConstant[
  b  = {0.5,  Name "Parameters/b"},    // punch half-width
  r  = {0.35, Name "Parameters/r"},    // corner radius
  H  = {1,    Name "Parameters/H"},    // punch height
  W  = {3,    Name "Parameters/W"},    // foundation half-width
  D  = {3,    Name "Parameters/D"},    // foundation depth
  hc = {0.05, Name "Parameters/hc"},   // size at the contact
  hmax = {0.5, Name "Parameters/hmax"} // size far from it
];

Mesh.SaveAll = 0;
Mesh.ElementOrder = 1;
Mesh.Algorithm = 6;               // Frontal-Delaunay (8 segfaults in gmsh 4.8.4)
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 1;  // Blossom
Mesh.SubdivisionAlgorithm = 1;    // split into quads -> all-quad
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

// ---------------- punch ----------------
Point(1) = {0, 0, 0};            // bottom centre
Point(2) = {b - r, 0, 0};        // start of the rounded corner
Point(4) = {b, r, 0};            // end of the rounded corner
Point(5) = {b, H, 0};
Point(6) = {0, H, 0};
Line(1) = {1, 2};                // flat bottom
Point(3) = {b - r, r, 0};        // the arc's centre
Circle(2) = {2, 3, 4};           // rounded corner
Line(3) = {4, 5};                // side
Line(4) = {5, 6};                // top (loaded)
Line(5) = {6, 1};                // axis
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};

// ---------------- foundation ----------------
Point(11) = {0, 0, 0};
Point(12) = {0, -D, 0};
Point(13) = {W, -D, 0};
Point(14) = {W, 0, 0};
Line(11) = {11, 12};             // axis
Line(12) = {12, 13};             // bottom (held)
Line(13) = {13, 14};             // right
Line(14) = {14, 11};             // top (contact)
Curve Loop(2) = {11, 12, 13, 14};
Plane Surface(2) = {2};

// sizes: 2 x the quad size (the subdivision halves the triangles)
Field[1] = Distance;
Field[1].CurvesList = {1, 2};
Field[1].NumPointsPerCurve = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = 2 * hc;
Field[2].SizeMax = 2 * hmax;
Field[2].DistMin = 0.05;
Field[2].DistMax = 2;
Background Field = 2;

Physical Surface("punch", 1) = {1};
Physical Curve("punch_bottom", 11) = {1, 2};
Physical Curve("punch_top", 12) = {4};
Physical Curve("punch_axis", 13) = {5};
Physical Curve("punch_side", 14) = {3};
Physical Surface("foundation", 2) = {2};
Physical Curve("foundation_axis", 21) = {11};
Physical Curve("foundation_bottom", 22) = {12};
Physical Curve("foundation_right", 23) = {13};
Physical Curve("foundation_top", 24) = {14};
