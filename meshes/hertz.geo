// hertz.geo -- scene S3: Hertz contact of a cylinder on a block (Q4 only).
//   cylinder: quarter disk of radius 1 centred at (0,1), x in [0,1], below
//             y=1; touches the block at the origin.
//   block:    [0,4]x[-4,0].
// The two bodies are separate, disconnected meshes.  The mesh size grows
// linearly with the distance r from the origin:
//   h_block(r)    = s * min(hmax, h0 + grading * max(r - rfine, 0))
//   h_cylinder(r) = ratio * h_block(r)      (non-matching contact meshes)
// with s = 2^-level, so every level halves the element size everywhere
// (~4x more nodes per level).  rfine = 0.2 covers the contact zone (a ~ 0.1).
// Negative levels make the coarse start of the adaptive loop (level -1: block
// quads of 0.05 at the contact, a few hundred dofs); a size field then replaces
// these sizes (remesh.h) and the geometry and physical names stay.
// Quads: Frontal-Delaunay triangles at size 2h, Blossom recombination, then
// one uniform quad subdivision (Mesh.SubdivisionAlgorithm = 1) -> all-quad.
//   gmsh -2 -format msh41 -setnumber level 2 hertz.geo -o hertz_2.msh
DefineConstant[
  level   = {0,     Min -2, Max 6, Step 1, Name "Parameters/level"},
  h0      = {0.025, Name "Parameters/h0"},      // block size at the contact, level 0
  ratio   = {0.7,   Name "Parameters/ratio"},   // cylinder size / block size
  grading = {0.25,  Name "Parameters/grading"}, // dh/dr away from the contact zone
  hmax    = {0.8,   Name "Parameters/hmax"},    // block size cap, level 0
  rfine   = {0.2,   Name "Parameters/rfine"}    // radius of the uniform fine zone
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

// ---------------- cylinder ----------------
Point(1) = {0, 0, 0};   // tip (contact point)
Point(2) = {1, 1, 0};
Point(3) = {0, 1, 0};   // centre
Circle(1) = {1, 3, 2};  // arc (contact surface)
Line(2) = {2, 3};       // top, y = 1
Line(3) = {3, 1};       // axis, x = 0
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};

// ---------------- block ----------------
Point(11) = {0, 0, 0};
Point(12) = {0, -4, 0};
Point(13) = {4, -4, 0};
Point(14) = {4, 0, 0};
Line(11) = {11, 12};    // axis, x = 0
Line(12) = {12, 13};    // bottom, y = -4
Line(13) = {13, 14};    // right, x = 4
Line(14) = {14, 11};    // top, y = 0 (contact surface)
Curve Loop(2) = {11, 12, 13, 14};
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
Field[5].CurvesList = {11, 12, 13, 14};
Field[5].PointsList = {11, 12, 13, 14};
Field[6] = Min;
Field[6].FieldsList = {4, 5};
Background Field = 6;

// ---------------- physical groups ----------------
Physical Surface("cylinder", 1) = {1};
Physical Curve("cylinder_arc", 11) = {1};
Physical Curve("cylinder_top", 12) = {2};
Physical Curve("cylinder_axis", 13) = {3};
Physical Surface("block", 2) = {2};
Physical Curve("block_axis", 21) = {11};
Physical Curve("block_bottom", 22) = {12};
Physical Curve("block_right", 23) = {13};
Physical Curve("block_top", 24) = {14};
