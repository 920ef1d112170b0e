//! LinuxCNC's G codes by name. A G code is held as its number times ten (`G33.1` → 331), so
//! that the codes with a decimal are exact integers; the reader matches on these names only.

/// A G code, times ten.
pub type GCode = i64;

pub const G0: GCode = 0; // rapid
pub const G1: GCode = 10; // feed
pub const G2: GCode = 20; // arc clockwise
pub const G3: GCode = 30; // arc counter-clockwise
pub const G4: GCode = 40; // dwell
pub const G7: GCode = 70; // diameter mode
pub const G8: GCode = 80; // radius mode
pub const G10: GCode = 100; // set offsets
pub const G17: GCode = 170; // XY plane
pub const G17_1: GCode = 171; // UV plane
pub const G18: GCode = 180; // ZX plane
pub const G18_1: GCode = 181; // WU plane
pub const G19: GCode = 190; // YZ plane
pub const G19_1: GCode = 191; // VW plane
pub const G20: GCode = 200; // inch
pub const G21: GCode = 210; // millimetre
pub const G28: GCode = 280; // go to the stored position
pub const G28_1: GCode = 281; // store it
pub const G30: GCode = 300; // go to the second stored position
pub const G30_1: GCode = 301; // store it
pub const G33: GCode = 330; // spindle-synchronised motion
pub const G33_1: GCode = 331; // rigid tapping
pub const G38_1: GCode = 381; // first probing code (G38.1 … G38.5)
pub const G38_5: GCode = 385; // last probing code
pub const G40: GCode = 400; // cutter compensation off
pub const G41: GCode = 410; // cutter compensation left
pub const G41_1: GCode = 411; // dynamic, left
pub const G42: GCode = 420; // cutter compensation right
pub const G42_1: GCode = 421; // dynamic, right
pub const G43: GCode = 430; // tool length offset
pub const G49: GCode = 490; // tool length offset off
pub const G53: GCode = 530; // machine coordinates
pub const G54: GCode = 540; // the default work offset
pub const G55: GCode = 550; // first other work offset (G55 … G59.3)
pub const G59_3: GCode = 593; // last work offset
pub const G61: GCode = 610; // exact path
pub const G61_1: GCode = 611; // exact stop
pub const G64: GCode = 640; // blending
pub const G70: GCode = 700; // finishing cycle
pub const G71: GCode = 710; // roughing cycle
pub const G71_1: GCode = 711;
pub const G72: GCode = 720; // facing cycle
pub const G72_1: GCode = 721;
pub const G73: GCode = 730; // chip-breaking drilling
pub const G74: GCode = 740; // left-hand tapping
pub const G76: GCode = 760; // threading cycle
pub const G80: GCode = 800; // canned cycle off
pub const G81: GCode = 810; // first drilling or boring cycle (G81 … G89)
pub const G89: GCode = 890; // last drilling or boring cycle
/// The last code of the G80 … G89 group as LinuxCNC numbers it (with decimals).
pub const G8X_LAST: GCode = 899;
pub const G90: GCode = 900; // absolute distance
pub const G90_1: GCode = 901; // absolute arc distance
pub const G91: GCode = 910; // incremental distance
pub const G91_1: GCode = 911; // incremental arc distance
pub const G92: GCode = 920; // coordinate offset (G92 … G92.3)
pub const G92_3: GCode = 923;
pub const G93: GCode = 930; // inverse-time feed
pub const G94: GCode = 940; // feed per minute
pub const G95: GCode = 950; // feed per revolution
pub const G96: GCode = 960; // constant surface speed
pub const G97: GCode = 970; // spindle speed in rpm
