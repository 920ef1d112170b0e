//! Custom macro B's variables: `#0` (always vacant), `#1`–`#33` (locals, one level per
//! `G65` call), `#100`–`#199` and `#500`–`#999` (commons). What the machine holds — the
//! system variables and a `#500`+ the program reads before it sets it (a common kept at
//! power-off) — is refused by name: ncthread reads no machine state.

use std::collections::HashMap;
use std::ops::Range;

use super::parse::{EvalError, Vars};

#[derive(Debug)]
pub struct Variables {
    /// The locals of each level: the main program's first.
    locals: Vec<[Option<f64>; 33]>,
    /// The commons the program has set (a vacant one too).
    commons: HashMap<i64, Option<f64>>,
}

impl Default for Variables {
    fn default() -> Self {
        Variables {
            locals: vec![[None; 33]],
            commons: HashMap::new(),
        }
    }
}

const RANGES: &str = "a variable is #0, #1 … #33 (locals), #100 … #199 or #500 … #999 (commons)";

/// What a system variable holds, by FANUC's numbering (0i-TF), for its refusal.
fn system(n: i64) -> &'static str {
    match n {
        1000..=1999 => "an interface signal of the machine",
        2000..=2999 => "a tool offset",
        3000..=3999 => "the control's alarm, clock or modal settings",
        4000..=4999 => "modal information of the block",
        5000..=5999 => "a position or a work offset",
        _ => "the machine's state",
    }
}

fn machine(range: &Range<usize>, message: String, help: &str) -> EvalError {
    EvalError {
        machine: true,
        ..EvalError::new(range, message, help)
    }
}

impl Variables {
    /// A new level of locals for a `G65` call, with its arguments.
    pub fn push(&mut self, args: [Option<f64>; 33]) {
        self.locals.push(args);
    }

    pub fn pop(&mut self) {
        if self.locals.len() > 1 {
            self.locals.pop();
        }
    }

    pub fn set(&mut self, n: i64, v: Option<f64>, range: &Range<usize>) -> Result<(), EvalError> {
        match n {
            1..=33 => {
                if let Some(level) = self.locals.last_mut() {
                    level[n as usize - 1] = v;
                }
                Ok(())
            }
            100..=199 | 500..=999 => {
                self.commons.insert(n, v);
                Ok(())
            }
            0 => Err(EvalError::new(
                range,
                "#0 is always vacant: it cannot be set".into(),
                RANGES,
            )),
            // The program's own alarm: the machine stops here with alarm 3000 + n.
            3000 => Err(EvalError::new(
                range,
                format!(
                    "#3000={}: the program raises its own alarm here and the machine stops",
                    v.map_or("vacant".into(), |v| v.to_string())
                ),
                "this run of the program ends in an alarm: check the values it was given",
            )),
            1000.. => Err(machine(
                range,
                format!(
                    "#{n} is a system variable ({}): setting it acts on the machine, which ncthread does not model",
                    system(n)
                ),
                "write what the program means to do with ordinary words",
            )),
            _ => Err(EvalError::new(
                range,
                format!("#{n} is not a variable of custom macro B"),
                RANGES,
            )),
        }
    }
}

impl Vars for Variables {
    fn get(&self, n: i64, range: &Range<usize>) -> Result<Option<f64>, EvalError> {
        match n {
            0 => Ok(None),
            1..=33 => Ok(self.locals.last().and_then(|l| l[n as usize - 1])),
            100..=199 => Ok(self.commons.get(&n).copied().flatten()),
            500..=999 => match self.commons.get(&n) {
                Some(v) => Ok(*v),
                None => Err(machine(
                    range,
                    format!(
                        "#{n} is read before the program sets it: #500 … #999 keep their values in the machine at power-off, which ncthread cannot know"
                    ),
                    "set the variable in the program before reading it, or write its value",
                )),
            },
            1000.. => Err(machine(
                range,
                format!(
                    "#{n} is a system variable ({}): its value is the machine's, which ncthread cannot know",
                    system(n)
                ),
                "write the value the program needs, or set a common variable (#100 …) to it",
            )),
            _ => Err(EvalError::new(
                range,
                format!("#{n} is not a variable of custom macro B"),
                RANGES,
            )),
        }
    }
}
