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
pub const G56: GCode = 560;
pub const G57: GCode = 570;
pub const G58: GCode = 580;
pub const G59: GCode = 590;
pub const G59_1: GCode = 591;
pub const G59_2: GCode = 592;
pub const G59_3: GCode = 593; // last work offset
pub const G61: GCode = 610; // exact path
pub const G61_1: GCode = 611; // exact stop
pub const G64: GCode = 640; // blending
pub const G70: GCode = 700; // finishing cycle
pub const G71: GCode = 710; // roughing cycle
pub const G71_1: GCode = 711;
pub const G71_2: GCode = 712;
pub const G72: GCode = 720; // facing cycle
pub const G72_1: GCode = 721;
pub const G72_2: GCode = 722;
pub const G73: GCode = 730; // chip-breaking drilling
pub const G74: GCode = 740; // left-hand tapping
pub const G76: GCode = 760; // threading cycle
pub const G80: GCode = 800; // canned cycle off
pub const G81: GCode = 810; // drilling (first drilling or boring cycle, G81 … G89)
pub const G82: GCode = 820; // drilling with a dwell
pub const G83: GCode = 830; // peck drilling
pub const G84: GCode = 840; // right-hand tapping
pub const G85: GCode = 850; // boring, feed out
pub const G86: GCode = 860; // boring, spindle stop, rapid out
pub const G87: GCode = 870; // back boring
pub const G88: GCode = 880; // boring, spindle stop, manual out
pub const G89: GCode = 890; // boring, dwell, feed out (last drilling or boring cycle)
/// The last code of the G80 … G89 group as LinuxCNC numbers it (with decimals).
pub const G8X_LAST: GCode = 899;
pub const G90: GCode = 900; // absolute distance
pub const G90_1: GCode = 901; // absolute arc distance
pub const G91: GCode = 910; // incremental distance
pub const G91_1: GCode = 911; // incremental arc distance
pub const G52: GCode = 520; // local coordinate offset
pub const G92: GCode = 920; // coordinate offset (G92 … G92.3)
pub const G92_1: GCode = 921; // offset off, parameters cleared
pub const G92_2: GCode = 922; // offset off, parameters kept
pub const G92_3: GCode = 923;
pub const G93: GCode = 930; // inverse-time feed
pub const G94: GCode = 940; // feed per minute
pub const G95: GCode = 950; // feed per revolution
pub const G96: GCode = 960; // constant surface speed
pub const G97: GCode = 970; // spindle speed in rpm
pub const G98: GCode = 980; // canned cycles retract to the initial level
pub const G99: GCode = 990; // canned cycles retract to R

/// The G codes LinuxCNC knows (its `_gees` table): any other one stops it where it reads the
/// line, also in a contour's subroutine ("G-code out of range" past G99.9, else "Unknown g
/// code used"). **\[evidence\]** LinuxCNC 2.9.0~pre1 `interp_array.cc`.
const LINUXCNC_G: [GCode; 88] = [
    0, 10, 20, 30, 40, 50, 51, 52, 53, 70, 80, 100, 170, 171, 180, 181, 190, 191, 200, 210, 280,
    281, 300, 301, 330, 331, 382, 383, 384, 385, 400, 410, 411, 420, 421, 430, 431, 432, 490, 520,
    530, 540, 550, 560, 570, 580, 590, 591, 592, 593, 610, 611, 640, 700, 710, 711, 712, 720, 721,
    722, 730, 740, 760, 800, 810, 820, 830, 840, 850, 860, 870, 880, 890, 900, 901, 910, 911, 920,
    921, 922, 923, 930, 940, 950, 960, 970, 980, 990,
];

/// Why LinuxCNC cannot read G code `code` (×10, `None`: not a whole tenth), as it says it.
pub fn linuxcnc_refuses(code: Option<GCode>) -> Option<&'static str> {
    match code {
        None => Some("G-code out of range"),
        Some(c) if !(0..=999).contains(&c) => Some("G-code out of range"),
        Some(c) if !LINUXCNC_G.contains(&c) => Some("Unknown g code used"),
        Some(_) => None,
    }
}

/// The M codes LinuxCNC knows (its `_ems` table): M0–M9, M19, M30, M48–M53, M60–M68,
/// M70–M73, M99 and the user's M100–M199. **\[evidence\]** as [`LINUXCNC_G`].
pub fn linuxcnc_knows_m(m: i64) -> bool {
    matches!(m, 0..=9 | 19 | 30 | 48..=53 | 60..=68 | 70..=73 | 99..=199)
}
