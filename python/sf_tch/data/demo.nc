% sample cutting program bundled with sf_tch: a plate 1 mm thick with a rounded outline
% cut outside the contour (G42), a slot cut inside (G41) and four helical holes.
% Absolute coordinates in mm, the plate's top at Z0. Rapids run at the safe height Z5
% only; the tool goes down and comes out of the material at feed. The tool radius
% comes from correction[0..1].
N10 G90 G17 G94
N20 G54 X0 Y0 Z0                ; zero offset: none (nothing moves)
N30 T1 M6
N40 M3 S12000
N50 G0 Z5                       ; safe height before the first move across the plate
(outline 120 x 80 with R10 corners, counter-clockwise, tool on the right = outside)
N60 G0 X10 Y-8
N70 G1 Z-1 F500                 ; down beside the plate
N80 M51                         ; torch/spindle on
N90 G42 G1 X10 Y0 F1500
N100 G1 X110 Y0
N110 G3 X120 Y10 I0 J10
N120 G1 Y70
N130 G3 X110 Y80 I-10 J0
N140 G1 X10
N150 G3 X0 Y70 I0 J-10
N160 G1 Y10
N170 G3 X10 Y0 I10 J0
N180 G40 G1 X10 Y-8
N190 M50                        ; torch/spindle off
N200 G1 Z0 F500                 ; out of the cut
N210 G0 Z5
(slot 40 x 10 with round ends, counter-clockwise, tool on the left = inside)
N220 G0 X60 Y40
N230 G1 Z-1 F500
N240 M51
N250 G41 G1 X60 Y35 F1200
N260 G1 X80
N270 G3 X80 Y45 I0 J5
N280 G1 X40
N290 G3 X40 Y35 I0 J-5
N300 G1 X60
N310 G40 G1 X60 Y40
N320 M50
N330 G1 Z0 F500
N340 G0 Z5
(four holes of R4 centred at X 30 50 70 90 and Y 20: one helical turn each from Z0 to Z-1)
P10 = 26                        ; X where the first hole starts (its centre is 4 mm right)
P11 = 20                        ; Y of the holes
P12 = 20                        ; spacing
FOR P1 = 0 TO 3
  G0 X(P10 + P1 * P12) Y(P11)
  G1 Z0 F500
  M51
  G2 X(P10 + P1 * P12) Y(P11) Z-1 I4 J0 F1200
  M50
  G1 Z0 F500
  G0 Z5
END
PRINT "plate done"
N400 G0 X0 Y0
N410 M5
N420 M30
