%G31FIRST.nc
[G31 with the infeed I under g31_infeed = "first" (I is the first cut) and g31_clearance = 1.]
[N30: V0 without I, so I = F/3 = 0.5 (the manual's default); cuts of equal cross-section,]
[depth 0.5*sqrt(n) = 0.5, 0.7071, 0.866, then 1.0 passes U0.92, so the last pass goes to 0.92.]
[Hand-derived: G0 X18 Z3; passes at X15, 14.5858, 14.268, 14.16 from Z3 to Z-21.5, lead 1.5,]
[each G0 X18, G0 Z3. N80: V1 with I0.4, U1: depths 0.4, 0.8, 1.0. Hand-derived: G0 X32 Z-21;]
[passes at X29.2, 28.4, 28 from Z-21 to Z-52, lead 2, each G0 X32, G0 Z-21.]
BEARBEITUNG
N10 T9 G97 S1000 M3
N20 G0 X30 Z10
N30 G31 F1.5 U0.92 B3 P1.5
N40 G0 X16 Z0
N50 G1 Z-20
N60 G80
N70 G0 X40 Z-21
N80 G31 V1 I0.4 U1 F2 B4 P2
N90 G0 X30 Z-25
N100 G1 Z-50
N110 G80
N120 G0 X100 Z50
N130 M30
ENDE
