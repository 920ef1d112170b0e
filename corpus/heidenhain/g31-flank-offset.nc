%G31FLANK.nc
[G31 with the flank offsets H1 and H2 under the sidecar profile: g31_clearance = 1.0 and]
[g31_h1 = "towards-end" (H1 moves each pass's start towards the thread's end, H2 the other]
[way) by its depth x tan A. N30: H1 A30, V0 IC4, U1.2 on D20 Z0..Z-30, B4 P2: depths 0.6,]
[0.8485, 1.0392, 1.2; tan 30 = 0.57735027, shifts 0.3464, 0.4899, 0.6, 0.6928 (rounded to]
[0.0001 mm). Hand-derived: G0 X22 Z4; passes from X18.8 Z3.6536, X18.303 Z3.5101, X17.9216]
[Z3.4, X17.6 Z3.3072, each to Z-32 at lead 2, then G0 X22, G0 Z4. N80: H2 (A not written:]
[30), V1 IC2, U1 on D30 Z-35..Z-60, B3 P1: depths 0.5, 1.0, shifts 0.2887 and 0.5774]
[towards the start. Hand-derived: G0 X32 Z-32; passes from X29 Z-31.7113 and X28 Z-31.4226]
[to Z-61 at lead 1.5, each G0 X32, G0 Z-32.]
BEARBEITUNG
N10 T9 G97 S1000 M3
N20 G0 X40 Z10
N30 G31 F2 U1.2 B4 P2 IC4 H1 A30
N40 G0 X20 Z0
N50 G1 Z-30
N60 G80
N70 G0 X40 Z-32
N80 G31 F1.5 U1 B3 P1 IC2 V1 H2
N90 G0 X30 Z-35
N100 G1 Z-60
N110 G80
N120 G0 X100 Z50
N130 M30
ENDE
