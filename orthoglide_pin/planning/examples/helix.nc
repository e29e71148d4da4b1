%
(3D helix: radius 40 mm, 5 turns down 50 mm, pitch 10 mm, then back up along the axis)
G21 G90 G17
G64 P0.01
G0 X40 Y0 Z30
G1 Z25 F1200
G2 X40 Y0 Z15 I-40 J0 F5000
G2 X40 Y0 Z5 I-40 J0
G2 X40 Y0 Z-5 I-40 J0
G2 X40 Y0 Z-15 I-40 J0
G2 X40 Y0 Z-25 I-40 J0
G0 X0 Y0
G0 Z30
M30
%
