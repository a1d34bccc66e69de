// patch_uniform.geo -- scene S2: non-matching contact patch test (Q4 only).
//   lower body [0,1]x[0,0.5], nl x ny quads
//   upper body [0,1]x[0.5,1], nu x ny quads
// The two bodies are separate, disconnected meshes (own points/lines even
// where corners coincide).  Both bodies are rotated rigidly about (0,0) by
// `angle` degrees (counter-clockwise).
//   gmsh -2 -format msh41 -setnumber angle 30 patch_uniform.geo -o patch.msh
//   gmsh -2 -format msh41 -setnumber body 1 patch_uniform.geo -o lower.msh
// `gap` lifts the upper body by that much (before the rotation): an initial gap
// (negative: an initial penetration). `shift` moves the upper body along x.
// `clockwise` 1 runs both curve loops clockwise: gmsh then writes every quad
// clockwise (as many real .geo files do), the same mesh otherwise.
DefineConstant[
  nl    = {10, Min 1, Step 1, Name "Parameters/nl"},
  nu    = {7,  Min 1, Step 1, Name "Parameters/nu"},
  ny    = {5,  Min 1, Step 1, Name "Parameters/ny"},
  body  = {0,  Choices {0 = "both", 1 = "lower only", 2 = "upper only"},
           Name "Parameters/body"},
  angle = {0,  Name "Parameters/angle"},
  gap   = {0,  Name "Parameters/gap"},
  shift = {0,  Name "Parameters/shift"},
  clockwise = {0, Choices {0, 1}, Name "Parameters/clockwise"}
];

Mesh.SaveAll = 0;
Mesh.RecombineAll = 1;
Mesh.ElementOrder = 1;

ca = Cos(angle * Pi / 180);
sa = Sin(angle * Pi / 180);

If (body != 2)
  // ---------------- lower body ----------------
  Point(1) = {0,                 0,                 0};
  Point(2) = {ca * 1,            sa * 1,            0};
  Point(3) = {ca * 1 - sa * 0.5, sa * 1 + ca * 0.5, 0};
  Point(4) = {-sa * 0.5,         ca * 0.5,          0};
  Line(1) = {1, 2};  // bottom
  Line(2) = {2, 3};  // right
  Line(3) = {3, 4};  // top (contact)
  Line(4) = {4, 1};  // left
  If (clockwise)
    Curve Loop(1) = {-4, -3, -2, -1};
  Else
    Curve Loop(1) = {1, 2, 3, 4};
  EndIf
  Plane Surface(1) = {1};
  Transfinite Curve{1, 3} = nl + 1;
  Transfinite Curve{2, 4} = ny + 1;
  Transfinite Surface{1} = {1, 2, 3, 4};
  Recombine Surface{1};

  Physical Surface("lower", 1) = {1};
  Physical Curve("lower_bottom", 11) = {1};
  Physical Curve("lower_right", 12) = {2};
  Physical Curve("lower_top", 13) = {3};
  Physical Curve("lower_left", 14) = {4};
  Physical Point("lower_origin", 31) = {1};
  Physical Point("lower_corner2", 33) = {2};
EndIf

If (body != 1)
  // ---------------- upper body ----------------
  y0 = 0.5 + gap;
  y1 = 1.0 + gap;
  x0 = shift;
  x1 = 1 + shift;
  Point(11) = {ca * x0 - sa * y0, sa * x0 + ca * y0, 0};
  Point(12) = {ca * x1 - sa * y0, sa * x1 + ca * y0, 0};
  Point(13) = {ca * x1 - sa * y1, sa * x1 + ca * y1, 0};
  Point(14) = {ca * x0 - sa * y1, sa * x0 + ca * y1, 0};
  Line(11) = {11, 12};  // bottom (contact)
  Line(12) = {12, 13};  // right
  Line(13) = {13, 14};  // top
  Line(14) = {14, 11};  // left
  If (clockwise)
    Curve Loop(2) = {-14, -13, -12, -11};
  Else
    Curve Loop(2) = {11, 12, 13, 14};
  EndIf
  Plane Surface(2) = {2};
  Transfinite Curve{11, 13} = nu + 1;
  Transfinite Curve{12, 14} = ny + 1;
  Transfinite Surface{2} = {11, 12, 13, 14};
  Recombine Surface{2};

  Physical Surface("upper", 2) = {2};
  Physical Curve("upper_bottom", 21) = {11};
  Physical Curve("upper_right", 22) = {12};
  Physical Curve("upper_top", 23) = {13};
  Physical Curve("upper_left", 24) = {14};
  Physical Point("upper_corner", 32) = {11};
EndIf
