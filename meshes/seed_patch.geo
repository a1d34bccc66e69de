// seed_patch.geo -- scene S1: the seed report's patch test (Q4 only).
//   lower body [0,1]x[0,0.5],       nlx x nly quads
//   upper body [0.25,0.75]x[0.5,0.75], nux x nuy quads
// The two bodies are separate, disconnected meshes.  The lower top edge is a
// single line covering x in [0,1].
//   gmsh -2 -format msh41 seed_patch.geo -o seed_patch.msh
//   gmsh -2 -format msh41 -setnumber body 2 seed_patch.geo -o upper.msh
DefineConstant[
  nlx  = {10, Min 1, Step 1, Name "Parameters/nlx"},
  nly  = {10, Min 1, Step 1, Name "Parameters/nly"},
  nux  = {5,  Min 1, Step 1, Name "Parameters/nux"},
  nuy  = {5,  Min 1, Step 1, Name "Parameters/nuy"},
  body = {0,  Choices {0 = "both", 1 = "lower only", 2 = "upper only"},
          Name "Parameters/body"}
];

Mesh.SaveAll = 0;
Mesh.RecombineAll = 1;
Mesh.ElementOrder = 1;

If (body != 2)
  // ---------------- lower body ----------------
  Point(1) = {0, 0,   0};
  Point(2) = {1, 0,   0};
  Point(3) = {1, 0.5, 0};
  Point(4) = {0, 0.5, 0};
  Line(1) = {1, 2};  // bottom
  Line(2) = {2, 3};  // right
  Line(3) = {3, 4};  // top (contact), whole x in [0,1]
  Line(4) = {4, 1};  // left
  Curve Loop(1) = {1, 2, 3, 4};
  Plane Surface(1) = {1};
  If (!Exists(m2d_size_field))  // remeshed by mortar2d -adapt: its size field instead
    Transfinite Curve{1, 3} = nlx + 1;
    Transfinite Curve{2, 4} = nly + 1;
    Transfinite Surface{1} = {1, 2, 3, 4};
    Recombine Surface{1};
  EndIf

  Physical Surface("lower", 1) = {1};
  Physical Curve("lower_bottom", 11) = {1};
  Physical Curve("lower_right", 12) = {2};
  Physical Curve("lower_top", 13) = {3};
  Physical Curve("lower_left", 14) = {4};
EndIf

If (body != 1)
  // ---------------- upper body ----------------
  Point(11) = {0.25, 0.5,  0};
  Point(12) = {0.75, 0.5,  0};
  Point(13) = {0.75, 0.75, 0};
  Point(14) = {0.25, 0.75, 0};
  Line(11) = {11, 12};  // bottom (contact)
  Line(12) = {12, 13};  // right
  Line(13) = {13, 14};  // top
  Line(14) = {14, 11};  // left
  Curve Loop(2) = {11, 12, 13, 14};
  Plane Surface(2) = {2};
  If (!Exists(m2d_size_field))
    Transfinite Curve{11, 13} = nux + 1;
    Transfinite Curve{12, 14} = nuy + 1;
    Transfinite Surface{2} = {11, 12, 13, 14};
    Recombine Surface{2};
  EndIf

  Physical Surface("upper", 2) = {2};
  Physical Curve("upper_bottom", 21) = {11};
  Physical Curve("upper_right", 22) = {12};
  Physical Curve("upper_top", 23) = {13};
  Physical Curve("upper_left", 24) = {14};
  Physical Point("upper_pin", 32) = {14};
EndIf
