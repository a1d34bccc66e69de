// indenter.geo -- a stiff rounded indenter pressed into a rubber block that
// rests on a base plate (Q4 only), the half x >= 0 of a scene symmetric about
// x = 0; units mm.
//   indenter: quarter disk of radius 10 centred at (0,10), x in [0,10], below
//             y = 10; its tip touches the block at the origin;
//   block:    [0,30]x[-20,0];
//   base:     [0,40]x[-25,-20], under the block.
// Three separate, disconnected meshes. Block and indenter sizes grow linearly
// with the distance r from the origin, as in hertz.geo:
//   h_block(r)    = s * min(hmax, h0 + grading * max(r - rfine, 0))
//   h_indenter(r) = ratio * h_block(r)      (non-matching contact meshes)
// ratio > 1: the indenter (non-mortar, 2e4 times stiffer) is the coarser
// side; a finer stiff non-mortar side rests on the soft side's facets (at
// ratio 0.7 every other node opened and the peak was 2.2 times Hertz's).
// the base plate uniform, s * hbase (its top does not match the block's bottom,
// whose cells are s * hmax there). s = 2^-level: every level halves the sizes.
// rfine = 0.8 covers the indenter's contact zone (a = 0.4 in options/indenter.opts).
// Negative levels are coarse starts for -adapt, whose size field replaces
// these sizes (remesh.h); the geometry and physical names stay.
//   gmsh -2 -format msh41 -setnumber level 1 indenter.geo -o indenter_1.msh
DefineConstant[
  level   = {1,    Min -2, Max 6, Step 1, Name "Parameters/level"},
  h0      = {0.1,  Name "Parameters/h0"},      // block size at the contact, level 0
  ratio   = {1.4,  Name "Parameters/ratio"},   // indenter size / block size
  grading = {0.25, Name "Parameters/grading"}, // dh/dr away from the contact zone
  hmax    = {3,    Name "Parameters/hmax"},    // block size cap, level 0
  hbase   = {2.2,  Name "Parameters/hbase"},   // base plate size, level 0
  rfine   = {0.8,  Name "Parameters/rfine"}    // radius of the uniform fine zone
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

s = 2 / 2^level;   // factor 2: the subdivision halves the triangle size

// ---------------- indenter ----------------
Point(1) = {0, 0, 0};    // tip (contact point)
Point(2) = {10, 10, 0};
Point(3) = {0, 10, 0};   // centre
Circle(1) = {1, 3, 2};   // arc (contact surface)
Line(2) = {2, 3};        // top, y = 10 (load)
Line(3) = {3, 1};        // axis, x = 0
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};

// ---------------- block ----------------
Point(11) = {0, 0, 0};
Point(12) = {0, -20, 0};
Point(13) = {30, -20, 0};
Point(14) = {30, 0, 0};
Line(11) = {11, 12};     // axis, x = 0
Line(12) = {12, 13};     // bottom, y = -20 (contact with the base)
Line(13) = {13, 14};     // right, x = 30 (free)
Line(14) = {14, 11};     // top, y = 0 (contact with the indenter)
Curve Loop(2) = {11, 12, 13, 14};
Plane Surface(2) = {2};

// ---------------- base plate ----------------
Point(21) = {0, -20, 0};
Point(22) = {0, -25, 0};
Point(23) = {40, -25, 0};
Point(24) = {40, -20, 0};
Line(21) = {21, 22};     // axis, x = 0
Line(22) = {22, 23};     // bottom, y = -25 (fixed)
Line(23) = {23, 24};     // right, x = 40 (free)
Line(24) = {24, 21};     // top, y = -20 (contact with the block)
Curve Loop(3) = {21, 22, 23, 24};
Plane Surface(3) = {3};

// ---------------- size fields ----------------
Field[1] = Distance;
Field[1].PointsList = {11};
Field[2] = Threshold;           // block size
Field[2].InField = 1;
Field[2].SizeMin = s * h0;
Field[2].SizeMax = s * hmax;
Field[2].DistMin = rfine;
Field[2].DistMax = rfine + (hmax - h0) / grading;
Field[3] = MathEval;            // indenter size
Field[3].F = Sprintf("%.17g * F2", ratio);
Field[4] = Restrict;
Field[4].InField = 3;
Field[4].SurfacesList = {1};
Field[4].CurvesList = {1, 2, 3};
Field[4].PointsList = {1, 2, 3};
Field[5] = Restrict;
Field[5].InField = 2;
Field[5].SurfacesList = {2};
Field[5].CurvesList = {11, 12, 13, 14};
Field[5].PointsList = {11, 12, 13, 14};
Field[6] = MathEval;            // base size
Field[6].F = Sprintf("%.17g", s * hbase);
Field[7] = Restrict;
Field[7].InField = 6;
Field[7].SurfacesList = {3};
Field[7].CurvesList = {21, 22, 23, 24};
Field[7].PointsList = {21, 22, 23, 24};
Field[8] = Min;
Field[8].FieldsList = {4, 5, 7};
Background Field = 8;

// ---------------- physical groups ----------------
Physical Surface("indenter", 1) = {1};
Physical Curve("indenter_tip", 11) = {1};
Physical Curve("indenter_top", 12) = {2};
Physical Curve("indenter_axis", 13) = {3};
Physical Surface("block", 2) = {2};
Physical Curve("block_axis", 21) = {11};
Physical Curve("block_bottom", 22) = {12};
Physical Curve("block_right", 23) = {13};
Physical Curve("block_top", 24) = {14};
Physical Surface("base", 3) = {3};
Physical Curve("base_axis", 31) = {21};
Physical Curve("base_bottom", 32) = {22};
Physical Curve("base_right", 33) = {23};
Physical Curve("base_top", 34) = {24};
