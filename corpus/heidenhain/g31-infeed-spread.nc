%G31SPREAD.nc
[The programs of g31-infeed-first.nc under g31_infeed = "spread": I bounds the cuts, and the]
[depth is spread over the fewest passes within it. N30: V0, I = F/3 = 0.5, U0.92: N =]
[ceil((0.92/0.5)^2) = ceil(3.3856) = 4, depths 0.92*sqrt(n/4) = 0.46, 0.6505, 0.7967, 0.92;]
[hand-derived passes at X15.08, 14.699, 14.4066, 14.16 (G0 X18 Z3 first, Z3 to Z-21.5). N80:]
[V1, I0.4, U1: N = ceil(2.5) = 3, depths 0.3333, 0.6667, 1.0; passes at X29.3334, 28.6666, 28]
[(G0 X32 Z-21 first, Z-21 to Z-52).]
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
