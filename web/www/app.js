// ncthread's browser page. Every result comes from the library compiled to WebAssembly
// (wasm_bindgen.convert / look / verify): this script only moves bytes and text between the
// page's controls and those functions. It makes no request: the WebAssembly is in
// ncthread-wasm.js, and the page's Content-Security-Policy forbids fetch.
"use strict";

(function () {
  const $ = (id) => document.getElementById(id);
  const loadStart = performance.now();
  const wasm = wasm_bindgen;

  /** The bytes of base64 text (the module in ncthread-wasm.js, the examples, share links). */
  function base64Bytes(text) {
    const raw = atob(text);
    const bytes = new Uint8Array(raw.length);
    for (let i = 0; i < raw.length; i++) bytes[i] = raw.charCodeAt(i);
    return bytes;
  }
  wasm.initSync({ module: base64Bytes(NCTHREAD_WASM) });

  const DIALECTS = JSON.parse(wasm.dialects());
  const state = {
    programs: [], // {name, bytes: Uint8Array, result}
    current: -1,
    profileName: "",
    operation: 0,
    generation: 0,
    firstShown: null,
  };

  // ---- the controls ---------------------------------------------------------------------

  function fillSelect(select, withAuto) {
    if (withAuto) select.add(new Option("auto (from the text)", "auto"));
    for (const d of DIALECTS) select.add(new Option(`${d.id} — ${d.title}`, d.id));
  }
  fillSelect($("from"), true);
  fillSelect($("to"), false);
  $("to").value = "iso";
  $("version").textContent = wasm.version();

  function showKeys() {
    const pre = $("keys");
    pre.textContent = "";
    let section = "";
    for (const line of wasm.profile_keys().split("\n")) {
      const header = line.match(/^\[(\w+)\]/);
      const key = line.match(/^(\w+)( *= .*?)(\s+#.*)?$/);
      if (header) section = header[1];
      if (key) {
        const span = document.createElement("span");
        span.className = "key";
        span.textContent = key[1];
        span.title = `add ${key[1]} to [${section}]`;
        const sec = section;
        span.addEventListener("click", () => addKey(sec, line.replace(/\s+#.*$/, "")));
        pre.append(span, key[2] + (key[3] || "") + "\n");
      } else {
        pre.append(line + "\n");
      }
    }
  }
  showKeys();

  /** Adds `line` to the profile's `[section]` (the section made when missing). */
  function addKey(section, line) {
    const profile = $("profile");
    const lines = profile.value.split("\n").filter((l, i, all) => l !== "" || i < all.length - 1);
    const at = lines.findIndex((l) => l.trim() === `[${section}]`);
    if (at < 0) {
      if (lines.length && lines[lines.length - 1] !== "") lines.push("");
      lines.push(`[${section}]`, line);
    } else {
      let end = at + 1;
      while (end < lines.length && !lines[end].startsWith("[")) end++;
      while (end > at + 1 && lines[end - 1].trim() === "") end--;
      lines.splice(end, 0, line);
    }
    profile.value = lines.join("\n") + "\n";
    profileChanged();
  }

  // The examples (examples.js: corpus programs with their profiles).
  for (const [i, [name]] of (window.NCTHREAD_EXAMPLES || []).entries()) {
    $("examples").add(new Option(name, String(i)));
  }
  $("examples").addEventListener("change", (e) => {
    const example = (window.NCTHREAD_EXAMPLES || [])[Number(e.target.value)];
    e.target.value = "";
    if (!example) return;
    const [name, program, profileName, profile] = example;
    setProfile(profileName, new TextDecoder().decode(base64Bytes(profile)), false);
    addProgram(name, base64Bytes(program));
  });


  // ---- programs -------------------------------------------------------------------------

  function addProgram(name, bytes) {
    state.programs.push({ name, bytes, result: null });
    select(state.programs.length - 1);
  }

  function select(index) {
    state.current = index;
    state.operation = 0;
    showTabs();
    const p = state.programs[index];
    // The text as ncthread decodes it (a legacy encoding included) arrives with the result.
    $("source").value = p ? new TextDecoder().decode(p.bytes) : "";
    run();
  }

  function showTabs() {
    const tabs = $("tabs");
    tabs.textContent = "";
    state.programs.forEach((p, i) => {
      const b = document.createElement("button");
      b.type = "button";
      b.className = "tab" + (p.result && !p.result.ok ? " refused" : "");
      b.textContent = p.name;
      b.setAttribute("aria-selected", String(i === state.current));
      b.addEventListener("click", () => select(i));
      tabs.append(b);
    });
  }

  /** Opens program files and profiles (`*.toml`): the profiles first, so that the programs
   * opened with them are read under them. */
  async function openFiles(files) {
    if (state.firstShown === null) window.ncthreadConvertStart = performance.now();
    const read = await Promise.all(
      [...files].map(async (file) => ({ name: file.name, bytes: new Uint8Array(await file.arrayBuffer()) })),
    );
    for (const f of read.filter((f) => /\.toml$/i.test(f.name))) {
      setProfile(f.name, new TextDecoder().decode(f.bytes), false);
    }
    const programs = read.filter((f) => !/\.toml$/i.test(f.name));
    for (const f of programs) state.programs.push({ name: f.name, bytes: f.bytes, result: null });
    if (programs.length) {
      select(state.programs.length - programs.length);
    } else {
      run();
    }
  }

  function setProfile(name, text, andRun = true) {
    state.profileName = name;
    $("profile").value = text;
    if (text.trim()) $("profile-pane").open = true;
    profileChanged(andRun);
  }

  function profileChanged(andRun = true) {
    const text = $("profile").value;
    if (!text.trim()) state.profileName = "";
    $("profile-state").textContent = text.trim()
      ? `(${state.profileName || "profile.toml"})`
      : "(built-in defaults)";
    if (andRun) run();
  }

  $("files").addEventListener("change", (e) => {
    openFiles(e.target.files);
    e.target.value = "";
  });
  $("profile-file").addEventListener("change", (e) => {
    openFiles(e.target.files);
    e.target.value = "";
  });
  $("profile-clear").addEventListener("click", () => setProfile("", ""));
  $("add").addEventListener("click", () => {
    addProgram(`program${state.programs.length + 1}.nc`, new Uint8Array());
    $("source").focus();
  });
  let typing = null;
  $("source").addEventListener("input", () => {
    if (state.current < 0) {
      state.programs.push({ name: "program.nc", bytes: new Uint8Array(), result: null });
      state.current = 0;
      showTabs();
    }
    state.programs[state.current].bytes = new TextEncoder().encode($("source").value);
    clearTimeout(typing);
    typing = setTimeout(run, 200);
  });
  $("profile").addEventListener("input", () => {
    clearTimeout(typing);
    typing = setTimeout(() => profileChanged(), 300);
  });
  for (const id of ["from", "to", "round"]) $(id).addEventListener("change", run);
  $("operation").addEventListener("change", () => {
    state.operation = Number($("operation").value);
    look();
  });

  // Drop anywhere.
  let dragDepth = 0;
  document.addEventListener("dragenter", (e) => {
    e.preventDefault();
    dragDepth++;
    $("drop-overlay").hidden = false;
  });
  document.addEventListener("dragleave", () => {
    if (--dragDepth <= 0) $("drop-overlay").hidden = true;
  });
  document.addEventListener("dragover", (e) => e.preventDefault());
  document.addEventListener("drop", (e) => {
    e.preventDefault();
    dragDepth = 0;
    $("drop-overlay").hidden = true;
    if (e.dataTransfer && e.dataTransfer.files.length) openFiles(e.dataTransfer.files);
  });

  // ---- running the library --------------------------------------------------------------

  function request() {
    const p = state.programs[state.current];
    return {
      name: p.name,
      bytes: p.bytes,
      from: $("from").value,
      to: $("to").value,
      profileName: state.profileName,
      profile: $("profile").value,
      round: $("round").checked,
    };
  }

  let downloadUrl = null;

  /** Converts the current program and shows the output, then verifies, explains and plots it. */
  function run() {
    const generation = ++state.generation;
    const status = $("status");
    if (state.current < 0) {
      status.dataset.state = "idle";
      return;
    }
    const r = request();
    const converted = wasm.convert(r.name, r.bytes, r.from, r.to, r.profileName, r.profile, r.round);
    const result = JSON.parse(converted.json);
    const bytes = converted.bytes;
    converted.free();
    state.programs[state.current].result = result;
    if (result.source !== undefined && document.activeElement !== $("source")) {
      $("source").value = result.source;
    }
    $("note").textContent = result.note || (result.message || "");
    showDiagnostics(result.diagnostics);
    if (downloadUrl) URL.revokeObjectURL(downloadUrl);
    downloadUrl = null;
    const download = $("download");
    if (result.ok) {
      $("output").textContent = result.output;
      $("encoding").textContent = `${result.file}, ${result.encoding}, ${bytes.length} bytes`;
      downloadUrl = URL.createObjectURL(new Blob([bytes], { type: "application/octet-stream" }));
      download.href = downloadUrl;
      download.download = result.file;
      download.textContent = `Download ${result.file}`;
      download.hidden = false;
      status.textContent = `Output (${r.to})`;
    } else {
      $("output").textContent = "";
      $("encoding").textContent = "";
      download.hidden = true;
      status.textContent = "Refused: no output (see the diagnostics)";
    }
    status.dataset.state = result.ok ? "done" : "refused";
    showTabs();
    if (state.firstShown === null) {
      state.firstShown = performance.now();
      window.ncthreadTiming = {
        loadToFirstResultMs: state.firstShown - loadStart,
        firstConversionMs: state.firstShown - (window.ncthreadConvertStart || state.firstShown),
      };
    }
    // What takes longer comes after the output has been shown.
    $("verdict").textContent = "…";
    setTimeout(() => {
      if (generation !== state.generation) return;
      const v = JSON.parse(wasm.verify(r.name, r.bytes, r.from, r.to, r.profileName, r.profile, r.round));
      $("verdict").textContent = v.verdict || v.message || "not verified (see the diagnostics)";
      $("verdict").className = "code " + (v.ok ? "ok" : "bad");
      look();
      document.body.dataset.generation = String(generation);
    }, 0);
  }

  function look() {
    const r = request();
    const l = JSON.parse(wasm.look(r.name, r.bytes, r.from, r.profileName, r.profile, state.operation));
    $("explain").textContent = l.ok ? l.explain : "(the program has errors)";
    $("plot").innerHTML = l.ok ? l.plot : "";
    const select = $("operation");
    select.textContent = "";
    select.add(new Option("the first thread", "0"));
    for (let i = 1; i <= (l.operations || 0); i++) select.add(new Option(`operation ${i}`, String(i)));
    select.value = String(state.operation);
  }

  /** The diagnostics as the CLI prints them, each `--> file:line:column` a link to the line. */
  function showDiagnostics(diagnostics) {
    const pre = $("diagnostics");
    pre.textContent = "";
    for (const line of diagnostics.text.split("\n")) {
      const at = line.match(/^(\s*-->\s+)(.*):(\d+):(\d+)$/);
      const level = line.match(/^(error|warning|note|help)(\[\w+\])?:/);
      if (at) {
        pre.append(at[1]);
        const a = document.createElement("a");
        a.href = "#";
        a.className = "line-link";
        a.dataset.line = at[3];
        a.dataset.column = at[4];
        a.textContent = `${at[2]}:${at[3]}:${at[4]}`;
        a.addEventListener("click", (e) => {
          e.preventDefault();
          // A profile's diagnostic points into the profile, any other into the program.
          const inProfile = at[2] === (state.profileName || "profile.toml") && $("profile").value.trim() !== "";
          if (inProfile) $("profile-pane").open = true;
          showLine(inProfile ? $("profile") : $("source"), Number(at[3]), Number(at[4]));
        });
        pre.append(a, "\n");
      } else if (level && (level[1] === "error" || level[1] === "warning")) {
        const b = document.createElement("span");
        b.className = level[1];
        b.textContent = level[0];
        pre.append(b, line.slice(level[0].length) + "\n");
      } else {
        pre.append(line + "\n");
      }
    }
    while (pre.lastChild && /^\n*$/.test(pre.lastChild.textContent)) pre.lastChild.remove();
  }

  /** Selects line `line` (1-based) from `column` of a text field and scrolls it into view. */
  function showLine(source, line, column) {
    const lines = source.value.split("\n");
    let start = 0;
    for (let i = 0; i < line - 1 && i < lines.length; i++) start += lines[i].length + 1;
    const text = lines[line - 1] || "";
    source.focus();
    source.setSelectionRange(start + Math.max(0, column - 1), start + text.length);
    const lineHeight = source.scrollHeight / Math.max(1, lines.length);
    source.scrollTop = Math.max(0, (line - 3) * lineHeight);
  }

  // ---- share links ------------------------------------------------------------------------

  function toBase64Url(bytes) {
    let text = "";
    for (let i = 0; i < bytes.length; i += 0x8000) {
      text += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
    }
    return btoa(text).replace(/\+/g, "-").replace(/\//g, "_").replace(/=+$/, "");
  }

  function fromBase64Url(text) {
    return base64Bytes(text.replace(/-/g, "+").replace(/_/g, "/"));
  }

  async function pipe(bytes, stream) {
    const out = new Blob([bytes]).stream().pipeThrough(stream);
    return new Uint8Array(await new Response(out).arrayBuffer());
  }

  /** The page's address with the current program, dialects and profile in its fragment. */
  async function shareLink() {
    const r = request();
    const data = {
      v: 1,
      name: r.name,
      program: toBase64Url(r.bytes),
      from: r.from,
      to: r.to,
      profileName: r.profileName,
      profile: r.profile,
      round: r.round,
    };
    const packed = await pipe(new TextEncoder().encode(JSON.stringify(data)), new CompressionStream("deflate-raw"));
    return location.href.split("#")[0] + "#p=" + toBase64Url(packed);
  }

  async function openShared(fragment) {
    const packed = fromBase64Url(fragment.slice(2));
    const data = JSON.parse(new TextDecoder().decode(await pipe(packed, new DecompressionStream("deflate-raw"))));
    if (data.v !== 1) throw new Error("a share link of another version");
    if ([...$("from").options].some((o) => o.value === data.from)) $("from").value = data.from;
    if ([...$("to").options].some((o) => o.value === data.to)) $("to").value = data.to;
    $("round").checked = !!data.round;
    state.profileName = data.profileName || "";
    $("profile").value = data.profile || "";
    if ((data.profile || "").trim()) $("profile-pane").open = true;
    $("profile-state").textContent = (data.profile || "").trim()
      ? `(${state.profileName || "profile.toml"})`
      : "(built-in defaults)";
    addProgram(data.name || "program.nc", fromBase64Url(data.program || ""));
  }

  $("share").addEventListener("click", async () => {
    if (state.current < 0) return;
    const link = await shareLink();
    const field = $("share-link");
    field.value = link;
    field.hidden = false;
    field.select();
    history.replaceState(null, "", link);
    try {
      await navigator.clipboard.writeText(link);
      $("note").textContent = "The link is copied: it holds the program, the dialects and the profile.";
    } catch (_) {
      $("note").textContent = "The link is in the field below: copy it.";
    }
  });

  // ---- start ------------------------------------------------------------------------------

  window.ncthreadReady = (async () => {
    if (location.hash.startsWith("#p=")) {
      try {
        window.ncthreadConvertStart = performance.now();
        await openShared(location.hash.slice(1));
      } catch (e) {
        $("note").textContent = `This share link could not be read: ${e.message}`;
      }
    }
  })();
  window.ncthreadPage = { state, run, shareLink, openFiles };
})();
