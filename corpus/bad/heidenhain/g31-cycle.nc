%G31.nc
[REFUSED (HEIR011): G31 with its end point in the block (X, Z: the MANUALplus 4110's form); the]
[620's G31 reads its contour after the call, up to G80 (corpus/heidenhain/g31-*.nc)]
BEARBEITUNG
N1 T9 G97 S1000 M3
N2 G0 X16 Z4
N3 G31 X16 Z-20 F1.5 U-0.92 I0.3
ENDE
