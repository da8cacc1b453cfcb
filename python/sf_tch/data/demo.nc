% sample cutting program bundled with sf_tch: a plate with a rounded outline,
% a slot and a drilled hole pattern (absolute coordinates, mm)
N10 G90 G17 G94
N20 G54 X0 Y0 Z0
N30 T1 M6
N40 M3 S12000
N50 F1500
(outline: rectangle 120 x 80 with R10 corners)
N60 G0 X10 Y0
N70 M51                         ; torch/spindle on
N80 G1 X110 Y0
N90 G3 X120 Y10 I0 J10
N100 G1 Y70
N110 G3 X110 Y80 I-10 J0
N120 G1 X10
N130 G3 X0 Y70 I0 J-10
N140 G1 Y10
N150 G3 X10 Y0 I10 J0
N160 M50                        ; torch/spindle off
(slot with semicircular ends)
N170 G0 X40 Y35
N180 M51
N190 G1 X80 F1200
N200 G2 X80 Y45 I0 J5
N210 G1 X40
N220 G2 X40 Y35 I0 J-5
N230 M50
(hole pattern: four holes, helical entry)
P10 = 25
P11 = 20
FOR P1 = 0 TO 3
  G0 X(P10 + P1 * 23.3333) Y(P11)
  M51
  G2 X(P10 + P1 * 23.3333) Y(P11) I4 J0 Z-1
  M50
END
N300 G0 X0 Y0
N310 M5
N320 M30
