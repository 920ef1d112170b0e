%G31INFEED.nc
[REFUSED (HEIR006): G31 V0 with the infeed I under a profile that declares the model]
[(g31_clearance) but not g31_infeed: whether I is the first cut or only bounds cuts spread]
[over the depth is not published. The same call with IC would be read.]
BEARBEITUNG
N10 T9 G97 S1000 M3
N20 G0 X40 Z10
N30 G31 F2 U1.2 B4 P2 I0.4 V0
N40 G0 X20 Z0
N50 G1 Z-30
N60 G80
N70 M30
ENDE
