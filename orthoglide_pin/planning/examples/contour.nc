%
(Contour: a rounded rectangle 100 x 70 mm with 15 mm corner arcs, then a 30 mm circle)
G21 G90 G17
G64 P0.01
G0 X-35 Y-35 Z5
G1 Z-2 F600
F6000
G1 X35 Y-35
G3 X50 Y-20 I0 J15
G1 Y20
G3 X35 Y35 I-15 J0
G1 X-35
G3 X-50 Y20 I0 J-15
G1 Y-20
G3 X-35 Y-35 I15 J0
G0 Z5
G0 X15 Y0
G1 Z-2 F600
G2 X15 Y0 I-15 J0 F4000 (full circle, clockwise)
G4 P0.2 (dwell)
G0 Z5
M30
%
