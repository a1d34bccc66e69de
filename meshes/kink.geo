// kink.geo -- the hydrostatic patch test across a shaped interface (Q4 only).
//   lower body: x in [-1,1], from y = -H up to the interface
//   upper body: x in [-1,1], from the interface up to y = H
// The interface runs from x = -1 to x = 1 through the point (xk, 0):
//   shape 0: two straight lines meeting at (xk, 0), their directions
//            tilt - turn/2 and tilt + turn/2 degrees (turn > 0: a valley);
//   shape 1: a circular arc turning by `turn` degrees between x = -1 and 1
//            (turn > 0: the centre above it), tilted by `tilt` about (xk, 0).
// Each body is two structured patches split by the vertical line x = xk, so
// both sides have a node at (xk, 0) (the kink), and nl (lower) and nu (upper)
// quads along each piece of the interface, ny through each body: nl != nu
// gives non-matching meshes. Exact answer under pressure p on every free face
// (lower_free, upper_free): sigma = -p I in both bodies (same material), the
// contact pressure p; u = -e (x - (xk, -H)) with e the uniform strain, so the
// supports lower_pin (xk, -H): xy, lower_roll (1, -H): y and upper_pin
// (xk, H): x carry no reaction.
//   gmsh -2 -format msh41 -setnumber turn 40 -setnumber nu 9 kink.geo -o kink40.msh
DefineConstant[
  turn  = {20,  Name "Parameters/turn"},
  shape = {0,   Choices {0 = "kink", 1 = "arc"}, Name "Parameters/shape"},
  tilt  = {0,   Name "Parameters/tilt"},
  xk    = {0.2, Name "Parameters/xk"},
  nl    = {7,   Min 1, Step 1, Name "Parameters/nl"},
  nu    = {10,  Min 1, Step 1, Name "Parameters/nu"},
  ny    = {4,   Min 1, Step 1, Name "Parameters/ny"},
  H     = {1,   Name "Parameters/H"}
];

Mesh.SaveAll = 0;
Mesh.RecombineAll = 1;
Mesh.ElementOrder = 1;

ct = Cos(tilt * Pi / 180);
st = Sin(tilt * Pi / 180);
// the interface's end points (ya at x = -1, yb at x = 1) before the tilt
If (shape == 0)
  ya = -(1 + xk) * Tan((tilt - turn / 2) * Pi / 180);
  yb = (1 - xk) * Tan((tilt + turn / 2) * Pi / 180);
Else
  R  = 1 / Sin(Fabs(turn) / 2 * Pi / 180);   // chord 2 from x = -1 to 1
  sg = turn > 0 ? 1 : -1;
  cy = sg * R * Cos(turn / 2 * Pi / 180);    // centre (0, cy) before the shift
  yk = cy - sg * Sqrt(R * R - xk * xk);      // the arc at x = xk, moved to y = 0
  // the arc's points and centre, shifted so that (xk, 0) is on it, turned by tilt about it
  ya = (cy - sg * Sqrt(R * R - 1)) - yk;
  yb = ya;
EndIf

// one body; t: tag offset, yo: its outer edge (y = -1 or 1), lower: 1 or 0
Macro MakeBody
  If (shape == 0)
    Point(t + 1) = {-1, ya, 0};
    Point(t + 3) = {1, yb, 0};
  Else
    Point(t + 1) = {xk + ct * (-1 - xk) - st * ya, st * (-1 - xk) + ct * ya, 0};
    Point(t + 3) = {xk + ct * (1 - xk) - st * yb, st * (1 - xk) + ct * yb, 0};
    Point(t + 9) = {xk + ct * (-xk) - st * (cy - yk), st * (-xk) + ct * (cy - yk), 0};
  EndIf
  Point(t + 2) = {xk, 0, 0};
  Point(t + 4) = {-1, yo, 0};
  Point(t + 5) = {xk, yo, 0};
  Point(t + 6) = {1, yo, 0};
  If (shape == 0)
    Line(t + 1) = {t + 1, t + 2};
    Line(t + 2) = {t + 2, t + 3};
  Else
    Circle(t + 1) = {t + 1, t + 9, t + 2};
    Circle(t + 2) = {t + 2, t + 9, t + 3};
  EndIf
  Line(t + 3) = {t + 4, t + 5};   // outer edge, left part
  Line(t + 4) = {t + 5, t + 6};   // outer edge, right part
  Line(t + 5) = {t + 4, t + 1};   // left side
  Line(t + 6) = {t + 5, t + 2};   // split line
  Line(t + 7) = {t + 6, t + 3};   // right side
  Curve Loop(t + 1) = {t + 3, t + 6, -(t + 1), -(t + 5)};
  Curve Loop(t + 2) = {t + 4, t + 7, -(t + 2), -(t + 6)};
  Plane Surface(t + 1) = {t + 1};
  Plane Surface(t + 2) = {t + 2};
  Transfinite Curve{t + 1, t + 2, t + 3, t + 4} = n + 1;
  Transfinite Curve{t + 5, t + 6, t + 7} = ny + 1;
  Transfinite Surface{t + 1} = {t + 4, t + 5, t + 2, t + 1};
  Transfinite Surface{t + 2} = {t + 5, t + 6, t + 3, t + 2};
  Recombine Surface{t + 1, t + 2};
Return

t = 0;  yo = -H; n = nl;
Call MakeBody;
t = 20; yo = H;  n = nu;
Call MakeBody;

// gmsh orients the quads by the curve loops: the lower body's loops run
// counter-clockwise, the upper body's clockwise; the program accepts either
Physical Surface("lower", 1) = {1, 2};
Physical Surface("upper", 2) = {21, 22};
Physical Curve("lower_top", 11) = {1, 2};
Physical Curve("lower_free", 12) = {3, 4, 5, 7};
Physical Curve("upper_bottom", 21) = {21, 22};
Physical Curve("upper_free", 22) = {23, 24, 25, 27};
Physical Point("lower_pin", 31) = {5};
Physical Point("lower_roll", 32) = {6};
Physical Point("upper_pin", 33) = {25};
