%G31LIMITS.nc
[REFUSED, under a profile that declares G31's whole model: what the model does not cut.]
[N30: H1 moving each start towards the end by depth x tan 30, 0.6928 mm at U1.2, further than]
[the run-in B0.5 (the tool would rapid into the stock; HEIR011). N80: a `/` (block skip) in the]
[contour (HEIR002). N130: IC0 (HEIR011). N180: G31 under G96 (HEIR011), as G33 is refused.]
BEARBEITUNG
N10 T9 G97 S1000 M3
N20 G0 X40 Z10
N30 G31 F2 U1.2 B0.5 P2 IC4 H1
N40 G0 X20 Z0
N50 G1 Z-30
N60 G80
N80 G31 F2 U1.2 B4 P2 IC4
N90 G0 X20 Z0
/N100 G1 Z-30
N110 G80
N130 G31 F2 U1.2 B4 P2 IC0
N140 G0 X20 Z0
N150 G1 Z-30
N160 G80
N170 G26 S2000
N175 G96 S150 M3
N180 G31 F2 U1.2 B4 P2 IC4
N190 G0 X20 Z0
N200 G1 Z-30
N210 G80
N220 M30
ENDE
