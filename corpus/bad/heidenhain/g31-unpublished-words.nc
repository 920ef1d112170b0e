%G31WORDS.nc
[REFUSED (HEIR011), under a profile that declares G31's model: each call uses a word whose]
[rule the manuals do not give: a flank offset H1 without the profile's g31_h1, two starts D2,]
[a start angle C30, a run-out K2, the infeed type V3, a transverse thread J1, an internal BD1,]
[alternating offsets H3; then NS/NE (a contour elsewhere) and a negative depth.]
BEARBEITUNG
N10 T9 G97 S1000 M3
N20 G0 X40 Z10
N30 G31 F2 U1.2 B4 P2 IC4 H1 A30
N40 G0 X20 Z0
N50 G1 Z-30
N60 G80
N70 G31 F2 U1.2 B4 P2 IC4 D2
N80 G0 X20 Z0
N90 G1 Z-30
N100 G80
N110 G31 F2 U1.2 B4 P2 IC4 C30 K2
N120 G0 X20 Z0
N130 G1 Z-30
N140 G80
N150 G31 F2 U1.2 B4 P2 I0.3 V3 J1 BD1
N151 G0 X20 Z0
N152 G1 Z-30
N153 G80
N155 G31 F2 U1.2 B4 P2 IC4 H3
N160 G0 X20 Z0
N170 G1 Z-30
N180 G80
N190 G31 NS40 NE50 F2 U1.2 B4 P2 IC4
N200 G31 F2 U-1.2 B4 P2 IC4
N210 G0 X20 Z0
N220 G1 Z-30
N230 G80
N240 M30
ENDE
