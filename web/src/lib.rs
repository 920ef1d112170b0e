//! ncthread in the browser: the library's own functions, compiled to WebAssembly and called
//! by the static page in `web/www/` (built by `scripts/build-web`). Nothing here converts,
//! explains or draws by itself: each function takes what the page holds (a program's bytes,
//! the dialects, the profile's text, `--round`) through the steps the CLI takes
//! (`ncthread::frontend`), and hands back what the CLI prints, as JSON.
//!
//! Every function is total: a bad dialect id, a bad profile or a refused program comes back
//! as a result with diagnostics, never as a panic.

use ncthread::diag::{self, Diagnostic, Format};
use ncthread::dialect::{self, DialectId};
use ncthread::frontend::{self, Read};
use ncthread::profile::Profile;
use ncthread::source::SourceFile;
use ncthread::{ConvertOptions, Unsupported};
use serde_json::{Value, json};
use wasm_bindgen::prelude::*;

/// The CLI's default `--max-errors`.
const MAX_ERRORS: usize = 50;

/// The dialects, for the page's menus: `[{"id", "title", "extension", "extensions"}]`.
#[wasm_bindgen]
pub fn dialects() -> String {
    let list: Vec<Value> = dialect::ALL
        .iter()
        .map(|d| {
            json!({
                "id": d.id().to_string(),
                "title": d.title(),
                "extension": d.extension(),
                "extensions": d.extensions(),
            })
        })
        .collect();
    Value::Array(list).to_string()
}

/// The library's version (Cargo's), for the page's footer.
#[wasm_bindgen]
pub fn version() -> String {
    ncthread::VERSION.to_string()
}

/// Every profile key with its values and defaults (a commented TOML file): the help beside
/// the page's profile editor.
#[wasm_bindgen]
pub fn profile_keys() -> String {
    ncthread::profile::KEYS.to_string()
}

/// What the page asks of one program.
struct Request<'a> {
    name: &'a str,
    bytes: &'a [u8],
    /// A dialect id, or `auto`.
    from: &'a str,
    to: &'a str,
    /// The profile's file name and text (an empty text: the built-in defaults).
    profile_name: &'a str,
    profile: &'a str,
    round: bool,
}

/// A program read for a request, with its profile and the options of its conversion.
struct Ready {
    read: Read,
    /// The conversion's options, the profile among them.
    options: ConvertOptions,
    /// What `--from auto` chose, and why.
    note: Option<String>,
    /// Diagnostics so far (a legacy encoding's note).
    diagnostics: Vec<Diagnostic>,
}

/// Why a request stopped before its program was read: a message, and diagnostics.
struct Stop {
    message: String,
    diagnostics: Vec<Diagnostic>,
}

fn dialect_of(id: &str, what: &str) -> Result<DialectId, Stop> {
    id.parse::<DialectId>().map_err(|_| Stop {
        message: format!(
            "{what} `{id}` is not a dialect (one of: {})",
            dialect::ALL
                .iter()
                .map(|d| d.id().to_string())
                .collect::<Vec<_>>()
                .join(", ")
        ),
        diagnostics: Vec::new(),
    })
}

fn profile_of(name: &str, text: &str) -> Result<Profile, Stop> {
    if text.trim().is_empty() {
        return Ok(Profile::default());
    }
    let name = if name.is_empty() {
        "profile.toml"
    } else {
        name
    };
    Profile::from_toml(&SourceFile::new(name, text)).map_err(|diagnostics| Stop {
        message: format!("the profile {name} has errors"),
        diagnostics,
    })
}

fn ready(r: &Request) -> Result<Ready, Stop> {
    let from = match r.from {
        "auto" | "" => None,
        id => Some(dialect_of(id, "--from")?),
    };
    let to = dialect_of(r.to, "--to")?;
    let profile = profile_of(r.profile_name, r.profile)?;
    let read = frontend::read(r.name.to_string(), r.bytes.to_vec(), from, None);
    let mut diagnostics = Vec::new();
    if let Some(d) = read.decoded.encoding_diagnostic(&read.src.name) {
        let refused = d.is_error();
        diagnostics.push(d);
        if refused {
            return Err(Stop {
                message: String::new(),
                diagnostics,
            });
        }
    }
    let note = read.auto_note(&profile, true);
    let options = ConvertOptions {
        round: r.round,
        profile,
        unsupported: Unsupported::Error,
        ..ConvertOptions::new(read.from, to)
    };
    Ok(Ready {
        read,
        options,
        note,
        diagnostics,
    })
}

/// The diagnostics as the CLI prints them, and one JSON object each (for links to lines).
fn diagnostics_json(diags: &[Diagnostic]) -> Value {
    json!({
        "text": frontend::render_diagnostics(diags, MAX_ERRORS, false),
        "items": diags.iter().map(Diagnostic::to_json_value).collect::<Vec<_>>(),
        "errors": diags.iter().filter(|d| d.is_error()).map(Diagnostic::count).sum::<usize>(),
        "json": diag::render_all(diags, Format::Json, false),
    })
}

fn stopped(stop: Stop) -> Value {
    json!({
        "ok": false,
        "from": Value::Null,
        "note": Value::Null,
        "message": stop.message,
        "diagnostics": diagnostics_json(&stop.diagnostics),
    })
}

/// A conversion's result: what the CLI writes (`bytes`, in the target's encoding) and what
/// it prints (`json`: `ok`, `from`, `note`, `file`, `encoding`, `output`, `diagnostics`).
#[wasm_bindgen]
pub struct Converted {
    json: String,
    bytes: Vec<u8>,
}

#[wasm_bindgen]
impl Converted {
    #[wasm_bindgen(getter)]
    pub fn json(&self) -> String {
        self.json.clone()
    }
    #[wasm_bindgen(getter)]
    pub fn bytes(&self) -> Vec<u8> {
        self.bytes.clone()
    }
}

/// The name of the output of `name` in dialect `to`: its stem and the target's extension.
fn output_name(name: &str, to: DialectId) -> String {
    let stem = std::path::Path::new(name)
        .file_stem()
        .map_or("program".into(), |s| s.to_string_lossy().into_owned());
    format!("{stem}.{}", dialect::get(to).extension())
}

/// `ncthread convert --from FROM --to TO [--round] [--profile P] NAME`.
#[wasm_bindgen]
#[allow(clippy::too_many_arguments)]
pub fn convert(
    name: &str,
    bytes: &[u8],
    from: &str,
    to: &str,
    profile_name: &str,
    profile: &str,
    round: bool,
) -> Converted {
    let request = Request {
        name,
        bytes,
        from,
        to,
        profile_name,
        profile,
        round,
    };
    let (json, bytes) = match ready(&request) {
        Err(stop) => (stopped(stop), Vec::new()),
        Ok(r) => converted(r),
    };
    Converted {
        json: json.to_string(),
        bytes,
    }
}

fn converted(r: Ready) -> (Value, Vec<u8>) {
    let Ready {
        read,
        options,
        note,
        mut diagnostics,
        ..
    } = r;
    let to = options.to;
    let file = output_name(&read.src.name, to);
    let kept = ncthread::text::Input::of(
        &read.src.text,
        read.decoded.encoding,
        &read.decoded.eof_mark,
        read.from == to,
    );
    let mut conversion = ncthread::convert(&read.src, &options);
    diagnostics.append(&mut conversion.diagnostics);
    let output_options = ncthread::text::OutputOptions::default();
    let bytes = conversion.output.as_ref().and_then(|text| {
        match ncthread::text::encode_output(text, &file, &output_options, &kept) {
            Ok(bytes) => Some(bytes),
            Err(d) => {
                diagnostics.push(*d);
                None
            }
        }
    });
    let json = json!({
        "ok": bytes.is_some(),
        "from": read.from.to_string(),
        "source": read.src.text,
        "note": note,
        "file": file,
        "encoding": output_options.encoding_for(&kept).name(),
        "output": conversion.output.filter(|_| bytes.is_some()),
        "diagnostics": diagnostics_json(&diagnostics),
    });
    (json, bytes.unwrap_or_default())
}

/// `ncthread explain` and `ncthread plot [--operation N]` (`operation` 0: the CLI's
/// default): `{"ok", "from", "note", "explain", "operations", "plot", "diagnostics"}`.
#[wasm_bindgen]
pub fn look(
    name: &str,
    bytes: &[u8],
    from: &str,
    profile_name: &str,
    profile: &str,
    operation: u32,
) -> String {
    let request = Request {
        name,
        bytes,
        from,
        // Explain and plot read the program only: any target will do.
        to: "iso",
        profile_name,
        profile,
        round: false,
    };
    match ready(&request) {
        Err(stop) => stopped(stop),
        Ok(r) => looked(r, operation as usize),
    }
    .to_string()
}

fn looked(r: Ready, operation: usize) -> Value {
    let Ready {
        read,
        options,
        note,
        mut diagnostics,
    } = r;
    let (program, mut parsed) =
        ncthread::parse(&read.src, read.from, &options.profile, Unsupported::Error);
    diagnostics.append(&mut parsed);
    diag::sort(&mut diagnostics);
    if diag::has_errors(&diagnostics) {
        return json!({
            "ok": false,
            "from": read.from.to_string(),
            "note": note,
            "diagnostics": diagnostics_json(&diagnostics),
        });
    }
    let options = ncthread::explain::Options::default();
    let ops = ncthread::explain::explain(&program, &options);
    let table = ncthread::explain::to_text(&ops, ncthread::explain::Table::Box);
    let chosen = match operation {
        0 => ncthread::explain::default_operation(&ops),
        n => ops.get(n - 1),
    };
    let simulation = ncthread::sim::simulate(&program);
    let svg = ncthread::plot::plot(&read.src.name, &simulation.segments, chosen);
    json!({
        "ok": true,
        "from": read.from.to_string(),
        "note": note,
        "explain": table,
        "operations": ops.len(),
        "plot": svg,
        "diagnostics": diagnostics_json(&diagnostics),
    })
}

/// `ncthread verify --from FROM --to TO [--round]`: `{"ok", "verdict", "diagnostics"}`,
/// `ok` when the two programs make the same motion.
#[wasm_bindgen]
#[allow(clippy::too_many_arguments)]
pub fn verify(
    name: &str,
    bytes: &[u8],
    from: &str,
    to: &str,
    profile_name: &str,
    profile: &str,
    round: bool,
) -> String {
    let request = Request {
        name,
        bytes,
        from,
        to,
        profile_name,
        profile,
        round,
    };
    match ready(&request) {
        Err(stop) => stopped(stop),
        Ok(r) => {
            let v = ncthread::verify_within(
                &r.read.src,
                &r.options,
                None,
                None,
                ncthread::sim::TOLERANCE,
            );
            let to = r.options.to;
            let (verdict, ok) = frontend::verdict(
                &v.outcome,
                &r.read.src,
                r.read.from,
                &format!("ncthread's {to} conversion"),
                to,
            );
            let mut diagnostics = r.diagnostics;
            diagnostics.extend(v.diagnostics);
            json!({
                "ok": ok,
                "verdict": verdict,
                "diagnostics": diagnostics_json(&diagnostics),
            })
        }
    }
    .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    const SEED: &[u8] =
        b"N10 G00 G95 S1000 M03\nN20 G00 X26.618 Z3.\nN30 G33 Z-9. I0. F1.5\nN40 G00 X29.\n";

    fn parsed(json: &str) -> Value {
        serde_json::from_str(json).expect("JSON")
    }

    #[test]
    fn converts_what_the_library_converts() {
        let c = convert("part.nc", SEED, "auto", "iso", "", "", false);
        let j = parsed(&c.json());
        assert_eq!(j["ok"], true, "{j}");
        assert_eq!(j["from"], "czech");
        assert_eq!(j["file"], "part.ngc");
        let src = SourceFile::new("part.nc", std::str::from_utf8(SEED).unwrap());
        let lib = ncthread::convert(
            &src,
            &ConvertOptions::new(dialect::czech::ID, dialect::iso::ID),
        );
        assert_eq!(c.bytes(), lib.output.unwrap().into_string().into_bytes());
        assert!(
            j["note"]
                .as_str()
                .unwrap()
                .starts_with("--from auto: reading part.nc as czech")
        );
    }

    #[test]
    fn bad_requests_are_results() {
        let j = parsed(&convert("p.nc", SEED, "klingon", "iso", "", "", false).json());
        assert_eq!(j["ok"], false);
        assert!(
            j["message"]
                .as_str()
                .unwrap()
                .contains("`klingon` is not a dialect")
        );
        let j = parsed(
            &convert(
                "p.nc",
                SEED,
                "czech",
                "iso",
                "p.toml",
                "[czech]\nnope = 1\n",
                false,
            )
            .json(),
        );
        assert_eq!(j["ok"], false);
        assert_eq!(j["diagnostics"]["items"][0]["line"], 2, "{j}");
        let j = parsed(&convert("p.nc", b"\0\0\x01binary", "auto", "iso", "", "", false).json());
        assert_eq!(j["ok"], false);
        assert_eq!(j["diagnostics"]["items"][0]["code"], "INP003", "{j}");
    }

    #[test]
    fn explains_plots_and_verifies() {
        let j = parsed(&look("part.nc", SEED, "czech", "", "", 0));
        assert_eq!(j["ok"], true, "{j}");
        assert!(j["plot"].as_str().unwrap().starts_with("<svg"));
        assert!(
            j["explain"]
                .as_str()
                .unwrap()
                .starts_with("operation 1: thread")
        );
        let j = parsed(&verify("part.nc", SEED, "czech", "fanuc", "", "", false));
        assert_eq!(j["ok"], true, "{j}");
        assert!(
            j["verdict"]
                .as_str()
                .unwrap()
                .starts_with("equivalent: part.nc (czech)")
        );
    }
}
