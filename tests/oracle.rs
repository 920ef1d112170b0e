//! LinuxCNC's rs274 as the oracle: every ISO conversion of the corpus must run in the real
//! interpreter, and the seed acceptance figures are read back from its canonical calls.
mod common;

use common::{Case, close, convert_case, corpus_cases, rs274, run_rs274, sync_moves};
use ncthread::Dialect;

fn case(name: &str) -> Case {
    corpus_cases()
        .into_iter()
        .find(|c| c.name == name)
        .unwrap_or_else(|| panic!("no corpus case {name}"))
}

fn iso(name: &str) -> String {
    let conversion = convert_case(&case(name), Dialect::Iso);
    conversion
        .output
        .unwrap_or_else(|| panic!("{name} was refused: {:?}", conversion.diagnostics))
}

#[test]
fn every_iso_conversion_runs_in_rs274() {
    let Some(cmd) = rs274() else { return };
    let mut checked = 0;
    for case in corpus_cases() {
        if let Some(ngc) = convert_case(&case, Dialect::Iso).output {
            run_rs274(cmd, &ngc).unwrap_or_else(|e| panic!("{}: {e}\n{ngc}", case.name));
            checked += 1;
        }
    }
    assert!(checked >= 12, "only {checked} conversions reached rs274");
}

#[test]
fn seed_entry_example_runs_from_71_798_to_64_then_to_z3() {
    let Some(cmd) = rs274() else { return };
    let moves =
        sync_moves(&run_rs274(cmd, &iso("czech/ex6b-entry-param-with-point+profile")).unwrap());
    assert_eq!(moves.len(), 2, "{moves:?}");
    let (entry, thread) = (&moves[0], &moves[1]);
    assert!(
        close(entry.from.0, 71.798, 1e-3) && close(entry.from.1, -100.0, 1e-4),
        "{entry:?}"
    );
    assert!(
        close(entry.to.0, 64.0, 1e-3) && close(entry.to.1, -88.0, 1e-4),
        "{entry:?}"
    );
    assert!(
        close(thread.to.0, 64.0, 1e-3) && close(thread.to.1, 3.0, 1e-4),
        "{thread:?}"
    );
    for m in &moves {
        assert!(close(m.z_lead, 6.0, 1e-5), "lead along Z {m:?}");
    }
}

#[test]
fn seed_taper_is_one_g33_with_z_lead_1_5() {
    let Some(cmd) = rs274() else { return };
    let moves = sync_moves(&run_rs274(cmd, &iso("czech/ex3-taper")).unwrap());
    assert_eq!(moves.len(), 1, "{moves:?}");
    let m = &moves[0];
    assert!(
        close(m.from.0, 226.0, 1e-4) && close(m.from.1, 3.0, 1e-4),
        "{m:?}"
    );
    assert!(
        close(m.to.0, 246.0, 1e-4) && close(m.to.1, -100.0, 1e-4),
        "{m:?}"
    );
    assert!(close(m.k, 1.50705, 1e-5), "{m:?}");
    assert!(close(m.z_lead, 1.5, 1e-5), "{m:?}");
}

#[test]
fn lead_250_through_a_parameter_converts() {
    let Some(cmd) = rs274() else { return };
    let moves = sync_moves(&run_rs274(cmd, &iso("czech/ex7-large-pitch")).unwrap());
    assert_eq!(moves.len(), 1);
    assert!(
        close(moves[0].k, 250.0, 1e-9) && close(moves[0].to.1, 200.0, 1e-4),
        "{moves:?}"
    );
}

#[test]
fn start_angle_becomes_the_same_helix_one_half_lead_earlier() {
    let Some(cmd) = rs274() else { return };
    let moves = sync_moves(&run_rs274(cmd, &iso("czech/multistart-i180")).unwrap());
    assert_eq!(moves.len(), 2);
    // Second start: lead 3, 180° → starts 1.5 mm before Z5, at the index pulse.
    assert!(
        close(moves[1].from.1, 6.5, 1e-4) && close(moves[1].to.1, -30.0, 1e-4),
        "{moves:?}"
    );
    assert!(close(moves[1].z_lead, 3.0, 1e-6));
}
