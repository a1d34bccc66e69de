// column.geo -- a column of nblock blocks [0,1]x[(i-1)h, i h], h = 0.25, each
// its own mesh (Q4 only): block i has 5 + 2 (i mod 4) x 2 quads, so that no
// two neighbours' meshes match along their interface. Physical names: block
// surfaces b1 ... bN; curves bI_bottom, bI_top; "left" holds every left edge;
// point b1_origin at (0, 0). The patch test across every interface (README,
// docs/trust.md): b1_bottom on rollers, left edges held in x, a pressure on
// bN_top, pairs bI+1_bottom:bI_top.
//   gmsh -2 -format msh41 -setnumber nblock 40 column.geo -o column_40.msh
DefineConstant[
  nblock = {9, Min 1, Step 1, Name "Parameters/nblock"}
];

Mesh.SaveAll = 0;
Mesh.RecombineAll = 1;
Mesh.ElementOrder = 1;

h = 0.25;
lefts[] = {};
For i In {1:nblock}
  t = 100 * i; y0 = (i - 1) * h; y1 = i * h; n = 5 + 2 * (i % 4);
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
  Transfinite Curve{t + 2, t + 4} = 3;
  Transfinite Surface{t + 1} = {t + 1, t + 2, t + 3, t + 4};
  Recombine Surface{t + 1};
  Physical Surface(Sprintf("b%g", i), t + 1) = {t + 1};
  Physical Curve(Sprintf("b%g_bottom", i), t + 11) = {t + 1};
  Physical Curve(Sprintf("b%g_top", i), t + 13) = {t + 3};
  lefts[] += {t + 4};
EndFor
Physical Curve("left", 1) = {lefts[]};
Physical Point("b1_origin", 2) = {101};
