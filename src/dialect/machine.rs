//! The block interpreter the front ends share: what one block switches (spindle, coolant,
//! program end), sorted by modal group, and the steps that turn it into IR items in one order.
//!
//! A front end reads its own words (the czech E/J, the НЦ-31 `*` groups and scaled words,
//! FANUC's U/W, LinuxCNC's O-words) and fills a [`Switches`]; its motion stays its own. The
//! steps run in LinuxCNC's order (`interp_convert.cc`, `convert_m` before `convert_g`):
//!
//! | step | group | words |
//! |------|-------|-------|
//! | [`Switches::spindle_mode`] | spindle speed mode | G96 / G97 |
//! | [`Switches::spindle`] | spindle speed and direction | S, M3 / M4 |
//! | [`Switches::coolant_on`] | coolant | M7 / M8 |
//! | (the front end's) | dwell or motion | G4, G0 … G33, cycles |
//! | [`Switches::coolant_off`] | coolant | M9 |
//! | [`Switches::spindle_stop`] | spindle | M5 |
//! | [`Switches::program_end`] | stopping | M2 / M30 |
//!
//! LinuxCNC switches M5 and M9 before the motion; the czech control and the НЦ-31 after it, so
//! that the block's own cut still has coolant and a turning spindle **[decided]**. A front end
//! calls the steps in the order its control takes; [`Switches::before_motion`] and
//! [`Switches::after_motion`] are the order of the controls that switch off after the motion.

use super::read::Reader;
use crate::ir::{Coolant, EndCode, ItemKind, SpindleDirection, SpindleMode};
use crate::source::Span;

/// One block's switching words, each with the span its item is stamped with.
#[derive(Debug, Default)]
pub(crate) struct Switches {
    /// G96 / G97: what the block's S means.
    pub spindle_mode: Option<(SpindleMode, Span)>,
    /// S and M3 / M4.
    pub spindle: Option<(Option<u32>, Option<SpindleDirection>, Span)>,
    /// M7 / M8 / M9, in the block's order.
    pub coolant: Vec<(Coolant, Span)>,
    /// M5.
    pub spindle_stop: Option<Span>,
    /// M2 / M30 (and the dialects' own end codes).
    pub end: Option<(EndCode, Span)>,
}

impl Switches {
    /// The speed mode first: the block's S is then in its unit.
    pub fn spindle_mode(&self, r: &mut Reader, number: Option<u32>) {
        if let Some((mode, span)) = self.spindle_mode {
            r.push(ItemKind::SpindleMode(mode), span, number);
        }
    }

    /// The speed and the direction, one item (a direction starts the spindle).
    pub fn spindle(&self, r: &mut Reader, number: Option<u32>) {
        if let Some((speed, direction, span)) = self.spindle
            && (speed.is_some() || direction.is_some())
        {
            r.push(ItemKind::Spindle { speed, direction }, span, number);
        }
    }

    /// Mist and flood on, in the block's order.
    pub fn coolant_on(&self, r: &mut Reader, number: Option<u32>) {
        for &(c, span) in self.coolant.iter().filter(|(c, _)| *c != Coolant::Off) {
            r.push(ItemKind::Coolant(c), span, number);
        }
    }

    /// Coolant off.
    pub fn coolant_off(&self, r: &mut Reader, number: Option<u32>) {
        for &(c, span) in self.coolant.iter().filter(|(c, _)| *c == Coolant::Off) {
            r.push(ItemKind::Coolant(c), span, number);
        }
    }

    /// The spindle stopped.
    pub fn spindle_stop(&self, r: &mut Reader, number: Option<u32>) {
        if let Some(span) = self.spindle_stop {
            r.push(ItemKind::SpindleStop, span, number);
        }
    }

    /// The program's end.
    pub fn program_end(&self, r: &mut Reader, number: Option<u32>) {
        if let Some((end, span)) = self.end {
            r.push(ItemKind::ProgramEnd(end), span, number);
        }
    }

    /// Every step that comes before the block's motion, for a control that switches off
    /// after it: speed mode, spindle, coolant on.
    pub fn before_motion(&self, r: &mut Reader, number: Option<u32>) {
        self.spindle_mode(r, number);
        self.spindle(r, number);
        self.coolant_on(r, number);
    }

    /// Every step after the block's motion: coolant off, spindle stop, program end.
    pub fn after_motion(&self, r: &mut Reader, number: Option<u32>) {
        self.coolant_off(r, number);
        self.spindle_stop(r, number);
        self.program_end(r, number);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dialect::read::Keep;
    use crate::source::SourceFile;

    #[test]
    fn switches_on_before_the_motion_and_off_after_it() {
        let src = SourceFile::new("t", "M3 S500 M8 M9 M5 M30\n".to_string());
        let mut r = Reader::new(&src, crate::dialect::iso::ID, Keep::Program);
        let span = src.span_in_line(src.lines().next().unwrap(), 0..2);
        let sw = Switches {
            spindle: Some((Some(500), Some(SpindleDirection::Clockwise), span)),
            coolant: vec![(Coolant::Flood, span), (Coolant::Off, span)],
            spindle_stop: Some(span),
            end: Some((EndCode::M30, span)),
            ..Switches::default()
        };
        sw.before_motion(&mut r, Some(10));
        r.push(
            ItemKind::Dwell {
                seconds: crate::fixed::Decimal::parse("1").unwrap(),
            },
            span,
            Some(10),
        );
        sw.after_motion(&mut r, Some(10));
        let (program, _) = r.finish();
        let kinds: Vec<_> = program.items.iter().map(|i| &i.kind).collect();
        assert!(matches!(
            kinds[0],
            ItemKind::Spindle {
                speed: Some(500),
                ..
            }
        ));
        assert_eq!(kinds[1], &ItemKind::Coolant(Coolant::Flood));
        assert!(matches!(kinds[2], ItemKind::Dwell { .. }));
        assert_eq!(kinds[3], &ItemKind::Coolant(Coolant::Off));
        assert_eq!(kinds[4], &ItemKind::SpindleStop);
        assert_eq!(kinds[5], &ItemKind::ProgramEnd(EndCode::M30));
        assert!(program.items.iter().all(|i| i.block_number == Some(10)));
    }
}
