// cattaneo.geo -- scene S7: Cattaneo-Mindlin, a cylinder pressed on a block
// of the same material, then sheared (Q4 only). The whole cylinder: the shear
// breaks the symmetry about x = 0.
//   cylinder: the half disk of radius 1 below its centre (0, 1), touching the
//             block at the origin; its flat top y = 1, x in [-1, 1], is loaded.
//   block:    [-4, 4] x [-4, 0], its bottom held.
// The two bodies are separate, disconnected meshes (own points). The mesh size
// grows linearly with the distance r from the origin, as in hertz.geo:
//   h_block(r)    = s * min(hmax, h0 + grading * max(r - rfine, 0))
//   h_cylinder(r) = ratio * h_block(r)      (non-matching contact meshes)
// with s = 2^-level: each level halves the sizes (about 4x the dofs). rfine
// = 0.2 covers the contact zone (half-width a ~ 0.1) and its edges.
//   gmsh -2 -format msh41 -setnumber level 3 cattaneo.geo -o cattaneo_3.msh
DefineConstant[
  level   = {2,     Min -2, Max 6, Step 1, Name "Parameters/level"},
  h0      = {0.025, Name "Parameters/h0"},      // block size at the contact, level 0
  ratio   = {0.7,   Name "Parameters/ratio"},   // cylinder size / block size
  grading = {0.25,  Name "Parameters/grading"}, // dh/dr away from the contact zone
  hmax    = {0.8,   Name "Parameters/hmax"},    // block size cap, level 0
  rfine   = {0.2,   Name "Parameters/rfine"}    // radius of the uniform fine zone
];

Mesh.SaveAll = 0;
Mesh.ElementOrder = 1;
Mesh.Algorithm = 6;               // Frontal-Delaunay
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 1;  // Blossom
Mesh.SubdivisionAlgorithm = 1;    // split into quads -> guaranteed all-quad
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;

s = 2 / 2^level;   // factor 2: the subdivision halves the triangle size

// ---------------- cylinder ----------------
Point(1) = {0, 0, 0};    // contact point
Point(2) = {1, 1, 0};
Point(3) = {0, 1, 0};    // centre
Point(4) = {-1, 1, 0};
Circle(1) = {4, 3, 1};   // arc, left half (contact surface)
Circle(2) = {1, 3, 2};   // arc, right half (contact surface)
Line(3) = {2, 4};        // top, y = 1
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};

// ---------------- block ----------------
Point(11) = {-4, 0, 0};
Point(12) = {-4, -4, 0};
Point(13) = {4, -4, 0};
Point(14) = {4, 0, 0};
Point(15) = {0, 0, 0};   // under the contact point: the size field's centre
Line(11) = {11, 12};     // left
Line(12) = {12, 13};     // bottom, y = -4
Line(13) = {13, 14};     // right
Line(14) = {14, 15};     // top, y = 0 (contact surface)
Line(15) = {15, 11};
Curve Loop(2) = {11, 12, 13, 14, 15};
Plane Surface(2) = {2};

// ---------------- size fields ----------------
Field[1] = Distance;
Field[1].PointsList = {15};
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
Field[4].PointsList = {1, 2, 3, 4};
Field[5] = Restrict;
Field[5].InField = 2;
Field[5].SurfacesList = {2};
Field[5].CurvesList = {11, 12, 13, 14, 15};
Field[5].PointsList = {11, 12, 13, 14, 15};
Field[6] = Min;
Field[6].FieldsList = {4, 5};
Background Field = 6;

// ---------------- physical groups ----------------
Physical Surface("cylinder", 1) = {1};
Physical Curve("cylinder_arc", 11) = {1, 2};
Physical Curve("cylinder_top", 12) = {3};
Physical Surface("block", 2) = {2};
Physical Curve("block_left", 21) = {11};
Physical Curve("block_bottom", 22) = {12};
Physical Curve("block_right", 23) = {13};
Physical Curve("block_top", 24) = {14, 15};
