// hertz_graded.geo -- scene S3 (Hertz), graded by hand toward the contact zone:
// the reference between uniform refinement (hertz.geo) and the adaptive loop
// (an estimator's size field): what grading alone buys. Same geometry and
// physical names as hertz.geo:
//   cylinder: quarter disk of radius 1 centred at (0,1), x in [0,1], below y=1;
//             touches the block at the origin.
//   block:    [0,4]x[-4,0].
// The element size grows geometrically, by `grading` from one element to the
// next, with the distance d from the contact zone (the part x in [0, zone] of
// each contact surface; in the cylinder, d is measured to its arc):
//   h_block(d)    = min(hmax, hc + (grading - 1) d),  hc = h0 / 2^level
//   h_cylinder(d) = ratio * h_block(d)        (non-matching contact meshes)
// hc is the quad size at the contact zone. The Hertz half-width is a ~ 0.1 at
// the load of options/hertz.opts: zone < a makes the fine zone narrower than
// the contact zone.
// Quads: Frontal-Delaunay triangles at size 2h, Blossom recombination, then
// one uniform quad subdivision (Mesh.SubdivisionAlgorithm = 1) -> all-quad.
//   gmsh -2 -format msh41 -setnumber level 2 hertz_graded.geo -o hertz_graded_2.msh
DefineConstant[
  level   = {0,     Name "Parameters/level"},    // halves hc per level
  h0      = {0.004, Name "Parameters/h0"},       // block quad size at the contact zone, level 0
  grading = {1.07,  Name "Parameters/grading"},  // size ratio of neighbouring elements
  zone    = {0.15,  Name "Parameters/zone"},     // half-width of the fine zone
  ratio   = {0.7,   Name "Parameters/ratio"},    // cylinder size / block size
  hmax    = {0.5,   Name "Parameters/hmax"}      // block size cap
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

hc = h0 / 2^level;

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
// factor 2: the triangles are made at twice the quad size (subdivision halves them).
// (Two separate formulas: a MathEval field that reads another one, F1, hangs gmsh 4.8.4.)
Field[1] = MathEval;            // block size
Field[1].F = Sprintf("2 * Min(%.17g, %.17g + %.17g * Sqrt(Max(x - %.17g, 0)^2 + y^2))", hmax, hc, grading - 1, zone);
Field[2] = MathEval;            // cylinder size; depth below the arc: 1 - |(x, y) - (0, 1)|
Field[2].F = Sprintf("%.17g * Min(%.17g, %.17g + %.17g * Sqrt(Max(x - %.17g, 0)^2 + (1 - Sqrt(x^2 + (y - 1)^2))^2))", 2 * ratio, hmax, hc, grading - 1, zone);
Field[3] = Restrict;
Field[3].InField = 2;
Field[3].SurfacesList = {1};
Field[3].CurvesList = {1, 2, 3};
Field[3].PointsList = {1, 2, 3};
Field[4] = Restrict;
Field[4].InField = 1;
Field[4].SurfacesList = {2};
Field[4].CurvesList = {11, 12, 13, 14};
Field[4].PointsList = {11, 12, 13, 14};
Field[5] = Min;
Field[5].FieldsList = {3, 4};
Background Field = 5;

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
