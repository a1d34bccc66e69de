// block.geo -- unit square [0,1]x[0,1], n x n structured quads (Q4).
// gmsh -2 -format msh41 -setnumber n 8 block.geo -o block.msh
DefineConstant[ n = {4, Min 1, Step 1, Name "Parameters/n"} ];

Mesh.SaveAll = 0;
Mesh.RecombineAll = 1;
Mesh.ElementOrder = 1;

Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {1, 1, 0};
Point(4) = {0, 1, 0};
Line(1) = {1, 2};   // bottom y=0
Line(2) = {2, 3};   // right  x=1
Line(3) = {3, 4};   // top    y=1
Line(4) = {4, 1};   // left   x=0
Curve Loop(1) = {1, 2, 3, 4};   // counter-clockwise
Plane Surface(1) = {1};

Transfinite Curve{1, 2, 3, 4} = n + 1;
Transfinite Surface{1} = {1, 2, 3, 4};
Recombine Surface{1};

Physical Surface("block") = {1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
Physical Point("origin") = {1};
