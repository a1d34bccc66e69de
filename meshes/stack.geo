// stack.geo -- three blocks stacked, two contact interfaces (Q4 only).
//   base [0,1]x[0,0.4]    nb x 4 quads
//   mid  [0,1]x[0.4,0.7]  nm x 3 quads
//   top  [0,1]x[0.7,1]    nt x 3 quads
// Separate, disconnected meshes; the interface meshes do not match at either
// interface (10, 7 and 13 quads along x by default). `body` 1, 2 or 3 writes
// that block alone (the three-file form of the same scene). `split` 1 makes
// mid's bottom two curves mid_bottom_a (x <= 3/7) and mid_bottom_b, the same
// nodes: the node at x = 3/7 lies on both (the shared-node rule's test).
// "left" holds the three left edges (one group on three bodies).
//   gmsh -2 -format msh41 stack.geo -o stack.msh
DefineConstant[
  nb   = {10, Min 1, Step 1, Name "Parameters/nb"},
  nm   = {7,  Min 1, Step 1, Name "Parameters/nm"},
  nt   = {13, Min 1, Step 1, Name "Parameters/nt"},
  body = {0,  Choices {0 = "all", 1 = "base", 2 = "mid", 3 = "top"}, Name "Parameters/body"},
  split = {0, Choices {0, 1}, Name "Parameters/split"}
];

Mesh.SaveAll = 0;
Mesh.RecombineAll = 1;
Mesh.ElementOrder = 1;

// one block [0,1]x[y0,y1], n x ny quads, points/lines/surface from tag t
Macro MakeBox
  Point(t + 1) = {0, y0, 0};
  Point(t + 2) = {1, y0, 0};
  Point(t + 3) = {1, y1, 0};
  Point(t + 4) = {0, y1, 0};
  Line(t + 1) = {t + 1, t + 2};  // bottom
  Line(t + 2) = {t + 2, t + 3};  // right
  Line(t + 3) = {t + 3, t + 4};  // top
  Line(t + 4) = {t + 4, t + 1};  // left
  Curve Loop(t + 1) = {t + 1, t + 2, t + 3, t + 4};
  Plane Surface(t + 1) = {t + 1};
  Transfinite Curve{t + 1, t + 3} = n + 1;
  Transfinite Curve{t + 2, t + 4} = ny + 1;
  Transfinite Surface{t + 1} = {t + 1, t + 2, t + 3, t + 4};
  Recombine Surface{t + 1};
Return

If (body == 0 || body == 1)
  t = 0; y0 = 0; y1 = 0.4; n = nb; ny = 4;
  Call MakeBox;
  Physical Surface("base", 1) = {1};
  Physical Curve("base_bottom", 11) = {1};
  Physical Curve("base_top", 13) = {3};
  Physical Curve("base_left", 14) = {4};
  Physical Point("base_origin", 31) = {1};
EndIf
If (body == 0 || body == 2)
  t = 10; y0 = 0.4; y1 = 0.7; n = nm; ny = 3;
  If (split == 0)
    Call MakeBox;
    Physical Curve("mid_bottom", 21) = {11};
  Else // the bottom in two lines through a node of the uniform division
    Point(15) = {3 / 7, 0.4, 0};
    Point(12) = {1, 0.4, 0};
    Point(13) = {1, 0.7, 0};
    Point(14) = {0, 0.7, 0};
    Point(11) = {0, 0.4, 0};
    Line(11) = {11, 15};
    Line(15) = {15, 12};
    Line(12) = {12, 13};
    Line(13) = {13, 14};
    Line(14) = {14, 11};
    Curve Loop(11) = {11, 15, 12, 13, 14};
    Plane Surface(11) = {11};
    Transfinite Curve{11} = 4;
    Transfinite Curve{15} = 5;
    Transfinite Curve{13} = 8;
    Transfinite Curve{12, 14} = 4;
    Transfinite Surface{11} = {11, 12, 13, 14};
    Recombine Surface{11};
    Physical Curve("mid_bottom", 21) = {11, 15};
    Physical Curve("mid_bottom_a", 25) = {11};
    Physical Curve("mid_bottom_b", 26) = {15};
  EndIf
  Physical Surface("mid", 2) = {11};
  Physical Curve("mid_top", 23) = {13};
  Physical Curve("mid_left", 24) = {14};
EndIf
If (body == 0 || body == 3)
  t = 20; y0 = 0.7; y1 = 1.0; n = nt; ny = 3;
  Call MakeBox;
  Physical Surface("top", 3) = {21};
  Physical Curve("top_bottom", 41) = {21};
  Physical Curve("top_top", 43) = {23};
  Physical Curve("top_left", 44) = {24};
EndIf
If (body == 0)
  Physical Curve("left", 50) = {4, 14, 24};
EndIf
