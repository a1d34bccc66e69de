// corner.geo -- contact surfaces with corners (Q4 only): a square punch with
// sharp corners on a foundation whose top may have a groove
// (tests/test_corner.py).
//   foundation [-2,2]x[-1,0]; groove (`groove` 1: at x in [1.2,1.5], where the
//   punch cannot reach; 2: at x in [-0.15,0.15], under the punch) `depth` deep
//   punch [-0.5,0.5]x[0,0.5], sharp corners, touching the foundation at y = 0
// Physical curves name each contact surface both ways: with its corners
// (punch_wrap: bottom and both sides; foundation_top: the whole top, groove
// included) and ended at them (punch_bottom; foundation_left / _right: the
// top left and right of the groove, or of x = 0.8 without one).
// `h`: the mesh size (quads: Blossom recombination, then one subdivision).
DefineConstant[
  groove = {1,    Choices {0 = "none", 1 = "away", 2 = "under the punch"}, Name "Parameters/groove"},
  depth  = {0.1,  Name "Parameters/depth"},
  h      = {0.05, Name "Parameters/h"}
];

Mesh.SaveAll = 0;
Mesh.ElementOrder = 1;
Mesh.Algorithm = 6;
Mesh.RecombineAll = 1;
Mesh.RecombinationAlgorithm = 1;
Mesh.SubdivisionAlgorithm = 1;
Mesh.MeshSizeFromPoints = 1;
Mesh.MeshSizeExtendFromBoundary = 1;
s = 2 * h; // the subdivision halves the size

// ---------------- foundation ----------------
g0 = groove == 2 ? -0.15 : 1.2;
g1 = groove == 2 ? 0.15 : 1.5;
Point(1) = {-2, -1, 0, 4 * s};
Point(2) = {2, -1, 0, 4 * s};
Point(3) = {2, 0, 0, s};
Point(8) = {-2, 0, 0, s};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(8) = {8, 1};
If (groove == 0)
  Point(4) = {0.8, 0, 0, s};
  Line(3) = {3, 4};
  Line(7) = {4, 8};
  Curve Loop(1) = {1, 2, 3, 7, 8};
  right() = {3};
  left() = {7};
  wall() = {};
Else
  Point(4) = {g1, 0, 0, s};
  Point(5) = {g1, -depth, 0, s};
  Point(6) = {g0, -depth, 0, s};
  Point(7) = {g0, 0, 0, s};
  Line(3) = {3, 4};
  Line(4) = {4, 5};
  Line(5) = {5, 6};
  Line(6) = {6, 7};
  Line(7) = {7, 8};
  Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8};
  right() = {3};
  left() = {7};
  wall() = {4, 5, 6};
EndIf
Plane Surface(1) = {1};

// ---------------- punch ----------------
Point(11) = {-0.5, 0, 0, s};
Point(12) = {0.5, 0, 0, s};
Point(13) = {0.5, 0.5, 0, s};
Point(14) = {-0.5, 0.5, 0, s};
Line(11) = {11, 12};
Line(12) = {12, 13};
Line(13) = {13, 14};
Line(14) = {14, 11};
Curve Loop(2) = {11, 12, 13, 14};
Plane Surface(2) = {2};

Physical Surface("foundation", 1) = {1};
Physical Surface("punch", 2) = {2};
Physical Curve("foundation_bottom", 11) = {1};
Physical Curve("foundation_top", 12) = {right(), wall(), left()};
Physical Curve("foundation_left", 13) = {left()};
Physical Curve("foundation_right", 14) = {right()};
Physical Curve("punch_bottom", 21) = {11};
Physical Curve("punch_wrap", 22) = {12, 11, 14};
Physical Curve("punch_top", 23) = {13};
Physical Point("punch_corner", 31) = {14};
