% sample cutting program bundled with sf_tch: a plate with a rounded outline cut
% outside the contour (G42), a slot cut inside (G41) and four helical holes.
% Absolute coordinates in mm; the tool radius comes from correction[0..1].
N10 G90 G17 G94
N20 G54 X0 Y0 Z0
N30 T1 M6
N40 M3 S12000
N50 F1500
(outline 120 x 80 with R10 corners, counter-clockwise, tool on the right = outside)
N60 G0 X10 Y-8
N70 M51                         ; torch/spindle on
N80 G42 G1 X10 Y0
N90 G1 X110 Y0
N100 G3 X120 Y10 I0 J10
N110 G1 Y70
N120 G3 X110 Y80 I-10 J0
N130 G1 X10
N140 G3 X0 Y70 I0 J-10
N150 G1 Y10
N160 G3 X10 Y0 I10 J0
N170 G40 G1 X10 Y-8
N180 M50                        ; torch/spindle off
(slot 40 x 10 with round ends, counter-clockwise, tool on the left = inside)
N190 G0 X60 Y40
N200 M51
N210 G41 G1 X60 Y35 F1200
N220 G1 X80
N230 G3 X80 Y45 I0 J5
N240 G1 X40
N250 G3 X40 Y35 I0 J-5
N260 G1 X60
N270 G40 G1 X60 Y40
N280 M50
(hole pattern: four holes, helical entry)
P10 = 25
P11 = 20
FOR P1 = 0 TO 3
  G0 X(P10 + P1 * 23.3333) Y(P11)
  M51
  G2 X(P10 + P1 * 23.3333) Y(P11) I4 J0 Z-1
  M50
END
PRINT "plate done"
N300 G0 X0 Y0
N310 M5
N320 M30
