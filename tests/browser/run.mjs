// The browser page in a real browser: headless Chromium (Debian's, driven by playwright-core)
// opens the page that scripts/build-web built, converts each seed program to every target
// through the page's controls and again through a share link, and holds every result against
// the CLI's, byte for byte: the output (the downloaded file), and for a refused program the
// diagnostics (code, line and column among them). Every request the page makes must be for a
// file of its own folder. The page is also opened from file://.
//
//   node tests/browser/run.mjs [--screenshot FILE]
//
// Environment: NCTHREAD_WEB (the built folder, default target/web), NCTHREAD_BIN (the CLI,
// default target/debug/ncthread), CHROMIUM (default /usr/bin/chromium).
// It prints the first conversion's time (reported, never asserted) and the seed G31
// program's share link to ISO.

import { chromium } from "playwright-core";
import { spawnSync } from "node:child_process";
import { createServer } from "node:http";
import { existsSync, readFileSync } from "node:fs";
import { basename, dirname, extname, join, resolve } from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";

const root = resolve(dirname(fileURLToPath(import.meta.url)), "../..");
const targetDir = process.env.CARGO_TARGET_DIR || join(root, "target");
const web = resolve(process.env.NCTHREAD_WEB || join(targetDir, "web"));
const cli = resolve(process.env.NCTHREAD_BIN || join(targetDir, "debug", "ncthread"));
const browserPath = process.env.CHROMIUM || "/usr/bin/chromium";
const screenshotAt = process.argv.indexOf("--screenshot");
const screenshot = screenshotAt > 0 ? resolve(process.argv[screenshotAt + 1]) : null;

// Every program printed in the seeds (corpus/czech/SEEDS.md, corpus/nc31/SEEDS.md, and the
// HEIDENHAIN page's G31 example), with the sidecar profile each has in the corpus.
const SEEDS = [
  "corpus/czech/ex1-multipass.nc",
  "corpus/czech/ex2-start-angle.nc",
  "corpus/czech/ex3-taper.nc",
  "corpus/czech/ex4-runout-constant.nc",
  "corpus/czech/ex5-runout-param.nc",
  "corpus/czech/ex6-entry-param.nc",
  "corpus/czech/ex6b-entry-param-with-point.nc",
  "corpus/czech/ex7-large-pitch.nc",
  "corpus/czech/ex8-params-two.nc",
  "corpus/nc31/g31-m36x1.5.nc",
  "corpus/nc31/g31-m36x1.5-incremental-z.nc",
  "corpus/nc31/g31-taper-fragment.nc",
  "corpus/nc31/g32-three-passes.nc",
  "corpus/nc31/g33-tap-m20x1.5.nc",
  "corpus/bad/heidenhain/g31-cycle.nc",
];
const G31 = "corpus/nc31/g31-m36x1.5.nc";

const failures = [];
function check(ok, what) {
  if (!ok) {
    failures.push(what);
    console.log(`FAIL ${what}`);
  }
}

for (const [what, path] of [["the built page", join(web, "index.html")], ["the CLI", cli], ["Chromium", browserPath]]) {
  if (!existsSync(path)) {
    console.error(`browser test: ${what} is missing at ${path} (scripts/build-web; cargo build)`);
    process.exit(2);
  }
}

function sidecar(program) {
  const p = join(root, program.replace(/\.[^.]+$/, ".profile.toml"));
  return existsSync(p) ? p : null;
}

/** The CLI's conversion of `program` (relative to root) to `to`: stdout bytes, stderr, exit code. */
function cliConvert(program, to) {
  const dir = join(root, dirname(program));
  const args = ["convert", "--from", "auto", "--to", to, basename(program)];
  const profile = sidecar(program);
  args.push(...(profile ? ["--profile", basename(profile)] : ["--no-profile"]));
  const r = spawnSync(cli, args, { cwd: dir, env: { ...process.env, NO_COLOR: "1" } });
  return { stdout: r.stdout, stderr: r.stderr.toString(), status: r.status };
}

/** The CLI's diagnostics as it prints them, without its own notes (`ncthread: …`). */
function cliDiagnostics(stderr) {
  return stderr
    .split("\n")
    .filter((l) => !l.startsWith("ncthread: "))
    .join("\n")
    .trim();
}

// ---- a static server for the folder, which records what it serves --------------------------

const TYPES = { ".html": "text/html", ".js": "text/javascript", ".css": "text/css" };
const served = [];
const server = createServer((req, res) => {
  const path = new URL(req.url, "http://x").pathname;
  const file = join(web, path === "/" ? "index.html" : path);
  served.push(path);
  if (!file.startsWith(web) || !existsSync(file)) {
    res.writeHead(404).end();
    return;
  }
  res.writeHead(200, { "content-type": TYPES[extname(file)] || "application/octet-stream" });
  res.end(readFileSync(file));
});
await new Promise((ok) => server.listen(0, "127.0.0.1", ok));
const origin = `http://127.0.0.1:${server.address().port}`;

const browser = await chromium.launch({
  executablePath: browserPath,
  args: [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
  ],
});
const context = await browser.newContext({ acceptDownloads: true, viewport: { width: 1500, height: 1100 } });
const requests = [];
context.on("request", (r) => requests.push(r.url()));
const pageErrors = [];

async function openPage(url) {
  const page = await context.newPage();
  page.on("pageerror", (e) => pageErrors.push(String(e)));
  page.on("console", (m) => {
    if (m.type() === "error") pageErrors.push(m.text());
  });
  await page.goto(url);
  await page.waitForFunction(() => window.ncthreadPage !== undefined);
  await page.evaluate(() => window.ncthreadReady);
  return page;
}

/** Waits until the page has shown every result of its last change. */
async function settled(page) {
  await page.waitForFunction(
    () =>
      window.ncthreadPage.state.generation > 0 &&
      document.body.dataset.generation === String(window.ncthreadPage.state.generation),
  );
}

/** What the page shows for its current program: the downloaded bytes, or the diagnostics. */
async function shown(page) {
  await settled(page);
  const state = await page.$eval("#status", (e) => e.dataset.state);
  const diagnostics = (await page.$eval("#diagnostics", (e) => e.textContent)).trim();
  if (state !== "done") return { state, diagnostics };
  const [download] = await Promise.all([page.waitForEvent("download"), page.click("#download")]);
  const bytes = readFileSync(await download.path());
  return { state, diagnostics, bytes, file: download.suggestedFilename() };
}

/** Holds what the page shows against the CLI's conversion. */
function compare(what, got, program, to) {
  const want = cliConvert(program, to);
  if (want.status === 0) {
    check(got.state === "done", `${what}: the CLI converts, the page shows ${got.state}: ${got.diagnostics}`);
    if (got.bytes) check(Buffer.compare(got.bytes, want.stdout) === 0, `${what}: the output differs from the CLI's`);
  } else {
    check(got.state === "refused", `${what}: the CLI refuses (exit ${want.status}), the page shows ${got.state}`);
    check(
      got.diagnostics === cliDiagnostics(want.stderr),
      `${what}: the diagnostics differ:\n--- page\n${got.diagnostics}\n--- CLI\n${cliDiagnostics(want.stderr)}`,
    );
    // The code, line and column of the first error are on the page as the CLI gives them.
    const first = want.stderr.match(/error\[(\w+)\][^\n]*\n\s*--> [^\n]*:(\d+):(\d+)/);
    if (first) check(got.diagnostics.includes(`:${first[2]}:${first[3]}`) && got.diagnostics.includes(first[1]), `${what}: ${first[1]} at ${first[2]}:${first[3]} not shown`);
  }
  return want.status === 0;
}

// The page's own menu is the list of targets.
const page = await openPage(`${origin}/`);
const targets = await page.$$eval("#to option", (os) => os.map((o) => o.value));
check(targets.length === 6, `the page offers ${targets.length} targets`);

let conversions = 0;
let refusals = 0;
let shared = 0;
let g31Link = null;
for (const program of SEEDS) {
  const profile = sidecar(program);
  // Through the controls: the program and its profile as files, then each target.
  await page.evaluate(() => {
    const s = window.ncthreadPage.state;
    s.programs.length = 0;
    s.current = -1;
    document.getElementById("profile-clear").click();
  });
  const files = [join(root, program)];
  if (profile) files.push(profile);
  await page.setInputFiles("#files", files);
  await page.waitForFunction((n) => window.ncthreadPage.state.programs[0]?.name === n, basename(program));
  for (const t of targets) {
    await page.selectOption("#to", t);
    const got = await shown(page);
    const ok = compare(`${program} → ${t} (controls)`, got, program, t);
    conversions += ok ? 1 : 0;
    refusals += ok ? 0 : 1;
    // The same through a share link, opened in a new page.
    const link = await page.evaluate(() => window.ncthreadPage.shareLink());
    if (program === G31 && t === "iso") g31Link = link;
    const other = await openPage(link);
    compare(`${program} → ${t} (share link)`, await shown(other), program, t);
    check((await other.$eval("#from", (e) => e.value)) === "auto", `${program} → ${t}: the link's --from`);
    await other.close();
    shared++;
  }
}

// The Share button: the link it shows opens the same conversion.
await page.setInputFiles("#files", [join(root, G31)]);
await page.selectOption("#to", "fanuc");
await settled(page);
await page.click("#share");
await page.waitForFunction(() => !document.getElementById("share-link").hidden);
const buttonLink = await page.$eval("#share-link", (e) => e.value);
const fromButton = await openPage(buttonLink);
compare(`${G31} → fanuc (Share button)`, await shown(fromButton), G31, "fanuc");
await fromButton.close();

// Files dropped on the page, in legacy encodings: decoded from their bytes as the CLI decodes
// them, and written back in the encoding the CLI writes.
const LEGACY = ["corpus/czech/windows-1250.nc", "corpus/nc31/pc-archive-cp866-crlf.nc"];
await page.evaluate(() => {
  const s = window.ncthreadPage.state;
  s.programs.length = 0;
  s.current = -1;
  document.getElementById("profile-clear").click();
});
const dropped = await page.evaluateHandle(
  (files) => {
    const dt = new DataTransfer();
    for (const f of files) dt.items.add(new File([new Uint8Array(f.bytes)], f.name));
    return dt;
  },
  LEGACY.map((p) => ({ name: basename(p), bytes: [...readFileSync(join(root, p))] })),
);
await page.dispatchEvent("body", "drop", { dataTransfer: dropped });
await page.waitForFunction((n) => window.ncthreadPage.state.programs.length === n, LEGACY.length);
for (const [i, program] of LEGACY.entries()) {
  await page.click(`#tabs button:nth-child(${i + 1})`);
  for (const t of ["iso", program.includes("czech") ? "czech" : "nc31"]) {
    await page.selectOption("#to", t);
    compare(`${program} → ${t} (dropped)`, await shown(page), program, t);
  }
  const text = await page.$eval("#source", (e) => e.value);
  check(/[^\x00-\x7f]/.test(text) && !text.includes("\ufffd"), `${program}: the page shows its text decoded`);
}

// The Examples menu: each example (a corpus program with its sidecar profile) converts as
// the CLI converts that file.
const examples = await page.$$eval("#examples option", (os) => os.slice(1).map((o) => [o.value, o.textContent]));
check(examples.length >= 6, `the page offers ${examples.length} examples`);
for (const [value, name] of examples) {
  const program = spawnSync("git", ["ls-files", `corpus/*/${name}`], { cwd: root }).stdout.toString().trim().split("\n")[0];
  await page.selectOption("#examples", value);
  await page.waitForFunction((n) => window.ncthreadPage.state.programs[window.ncthreadPage.state.current]?.name === n, name);
  await page.selectOption("#to", "iso");
  compare(`example ${program} → iso`, await shown(page), program, "iso");
}

// A diagnostic's location is a link to its line in the source.
await page.setInputFiles("#files", [join(root, "corpus/czech/ex6-entry-param.nc")]);
await page.selectOption("#to", "iso");
await settled(page);
const link = await page.$("#diagnostics a.line-link");
check(link !== null, "a refused program's diagnostic links to its line");
if (link) {
  await link.click();
  const line = Number(await link.getAttribute("data-line"));
  const selected = await page.$eval("#source", (e) => e.value.slice(e.selectionStart, e.selectionEnd));
  const lineText = (await page.$eval("#source", (e) => e.value)).split("\n")[line - 1];
  check(selected.length > 0 && lineText.endsWith(selected), `the link selects line ${line} (${JSON.stringify(selected)})`);
}

// A bad profile: its diagnostic (the CLI's PF001) links to the line in the profile editor.
await page.evaluate(() => {
  const p = document.getElementById("profile");
  p.value = "[czech]\nbogus = 1\n";
  p.dispatchEvent(new Event("input"));
});
await page.waitForFunction(() => document.getElementById("note").textContent.includes("has errors"));
const profileLink = await page.$("#diagnostics a.line-link");
check(profileLink !== null && (await profileLink.textContent()) === "profile.toml:2:1", "a profile's diagnostic names its line");
if (profileLink) {
  await profileLink.click();
  const selected = await page.$eval("#profile", (e) => e.value.slice(e.selectionStart, e.selectionEnd));
  check(selected === "bogus = 1", `a profile's diagnostic selects its line in the profile (${JSON.stringify(selected)})`);
}

// The first conversion of the seed G31 program on a freshly loaded page.
const fresh = await openPage(`${origin}/`);
await fresh.setInputFiles("#files", [join(root, G31)]);
await shown(fresh);
const timing = await fresh.evaluate(() => window.ncthreadTiming);
const plotted = await fresh.$eval("#plot", (e) => e.querySelector("svg") !== null);
const explained = await fresh.$eval("#explain", (e) => e.textContent);
const verdict = await fresh.$eval("#verdict", (e) => e.textContent);
check(plotted, "the G31 program is plotted");
check(/operation 1: G31/.test(explained) || explained.includes("pass"), "the G31 program is explained");
check(verdict.startsWith("equivalent:"), `the G31 program verifies: ${verdict}`);
if (screenshot) {
  await fresh.screenshot({ path: screenshot, fullPage: true });
  console.log(`screenshot: ${screenshot}`);
}
await fresh.close();

// From file://, with no server at all.
const local = await openPage(pathToFileURL(join(web, "index.html")).href);
await local.setInputFiles("#files", [join(root, G31)]);
compare(`${G31} → iso (file://)`, await shown(local), G31, "iso");
await local.close();

await page.close();
await browser.close();
server.close();

// Every request was for the page's own files (or the page's own blob: downloads).
const outside = requests.filter(
  (u) => !(u.startsWith(origin + "/") || u.startsWith(pathToFileURL(web).href + "/") || u.startsWith("blob:") || u.startsWith("data:")),
);
check(outside.length === 0, `requests outside the page's folder: ${outside.join(", ")}`);
const foreign = served.filter((p) => !["/", "/index.html", "/style.css", "/app.js", "/ncthread.js", "/ncthread-wasm.js", "/examples.js"].includes(p.split("?")[0]));
check(foreign.length === 0, `the server was asked for files the page does not have: ${foreign.join(", ")}`);
check(pageErrors.length === 0, `errors in the page: ${pageErrors.join("; ")}`);

console.log(
  `browser: ${SEEDS.length} seed programs × ${targets.length} targets: ${conversions} converted, ${refusals} refused, each the CLI's byte for byte; ${shared} share links opened; ${requests.length} requests, all the page's own`,
);
console.log(
  `browser: the seed G31 program's first conversion showed ${timing.firstConversionMs.toFixed(1)} ms after its file was given (page load to result ${timing.loadToFirstResultMs.toFixed(1)} ms)`,
);
console.log(`browser: share link of ${G31} to iso: ${g31Link ? g31Link.replace(origin + "/", "index.html") : "(none)"}`);
if (failures.length) {
  console.log(`browser: ${failures.length} failure(s)`);
  process.exit(1);
}
console.log("browser: ok");
