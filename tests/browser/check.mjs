// Opens vpcut HTML reports in headless Chromium (WebGL2 in software: SwiftShader) over the
// DevTools protocol on a pipe (no npm package needed) and checks each page:
//   - no console errors and no uncaught exceptions;
//   - the 3D view is ready and draws the part: enough non-background pixels on the canvas,
//     most of the middle of the picture (where the framed part is: a nut shows its bore);
//   - clicking a finding's row (a real mouse click) flies the camera to its point;
//   - the per-turn and findings tables hold the report's numbers (the report embedded in
//     the page, and the report.json the same run wrote);
//   - a click on a heading sorts the findings.
// Usage: node check.mjs CHROMIUM page.html report.json [page.html report.json ...]
// Writes each page's screenshot beside it as PAGE.png, and the 3D view after the click on
// a finding as PAGE.finding.png.
import { spawn } from "node:child_process";
import { readFileSync, writeFileSync } from "node:fs";
import { resolve } from "node:path";
import { pathToFileURL } from "node:url";

const [chromium, ...pairs] = process.argv.slice(2);
if (!chromium || pairs.length === 0 || pairs.length % 2 !== 0) {
  console.error("usage: node check.mjs CHROMIUM page.html report.json [...]");
  process.exit(2);
}

const proc = spawn(
  chromium,
  [
    "--headless=new",
    "--no-sandbox",
    "--use-angle=swiftshader",
    "--enable-unsafe-swiftshader",
    "--no-first-run",
    "--no-default-browser-check",
    "--disable-extensions",
    "--remote-debugging-pipe",
    "about:blank",
  ],
  { stdio: ["ignore", "ignore", "pipe", "pipe", "pipe"] }
);
let stderr = "";
proc.stdio[2].on("data", (d) => (stderr += d));
const toChrome = proc.stdio[3];
const fromChrome = proc.stdio[4];

let nextId = 1;
const waiting = new Map();
const listeners = [];
let pending = Buffer.alloc(0);
fromChrome.on("data", (chunk) => {
  pending = Buffer.concat([pending, chunk]);
  let end;
  while ((end = pending.indexOf(0)) >= 0) {
    const msg = JSON.parse(pending.subarray(0, end).toString("utf8"));
    pending = pending.subarray(end + 1);
    if (msg.id !== undefined && waiting.has(msg.id)) {
      const { ok, bad } = waiting.get(msg.id);
      waiting.delete(msg.id);
      if (msg.error) bad(new Error(JSON.stringify(msg.error)));
      else ok(msg.result);
    } else if (msg.method) {
      for (const l of listeners) l(msg);
    }
  }
});
function send(method, params = {}, sessionId) {
  const id = nextId++;
  const msg = { id, method, params };
  if (sessionId) msg.sessionId = sessionId;
  toChrome.write(JSON.stringify(msg) + "\0");
  return new Promise((ok, bad) => {
    waiting.set(id, { ok, bad });
    setTimeout(() => bad(new Error(`${method}: no answer in 60 s`)), 60000).unref();
  });
}
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

let failures = 0;
function check(ok, what) {
  console.log(`  ${ok ? "ok  " : "FAIL"} ${what}`);
  if (!ok) failures++;
}

async function checkPage(page, reportPath) {
  console.log(`${page}`);
  const { targetId } = await send("Target.createTarget", { url: "about:blank" });
  const { sessionId } = await send("Target.attachToTarget", { targetId, flatten: true });
  const s = (m, p) => send(m, p, sessionId);
  const errors = [];
  let loaded = false;
  const listener = (msg) => {
    if (msg.sessionId !== sessionId) return;
    if (msg.method === "Runtime.exceptionThrown") {
      errors.push("exception: " + JSON.stringify(msg.params.exceptionDetails).slice(0, 400));
    } else if (msg.method === "Runtime.consoleAPICalled" && msg.params.type === "error") {
      errors.push("console.error: " + JSON.stringify(msg.params.args).slice(0, 400));
    } else if (msg.method === "Log.entryAdded" && msg.params.entry.level === "error") {
      errors.push("log: " + msg.params.entry.text);
    } else if (msg.method === "Page.loadEventFired") {
      loaded = true;
    }
  };
  listeners.push(listener);
  await s("Runtime.enable");
  await s("Log.enable");
  await s("Page.enable");
  await s("Emulation.setDeviceMetricsOverride", {
    width: 1280,
    height: 900,
    deviceScaleFactor: 1,
    mobile: false,
  });
  await s("Page.navigate", { url: pathToFileURL(resolve(page)).href });
  const evaluate = async (expression) => {
    const r = await s("Runtime.evaluate", { expression, returnByValue: true, awaitPromise: true });
    if (r.exceptionDetails) throw new Error(`${expression}: ${JSON.stringify(r.exceptionDetails)}`);
    return r.result.value;
  };
  for (let t = 0; t < 600 && !loaded; t++) await sleep(100);
  check(loaded, "the page loads");
  let state = null;
  for (let t = 0; t < 600; t++) {
    state = await evaluate(
      "window.vpcutViewer ? {ready: window.vpcutViewer.ready, error: window.vpcutViewer.error, frames: window.vpcutViewer.frames} : null"
    );
    if (state && (state.ready || state.error)) break;
    await sleep(100);
  }
  check(state && state.ready && !state.error, `the 3D view is ready (${JSON.stringify(state)})`);
  const report = JSON.parse(readFileSync(reportPath, "utf8"));

  // The part on the canvas, in the home view.
  await evaluate("window.vpcutViewer.draw(), true");
  const px = await evaluate(`(() => {
    const c = document.getElementById("view3d");
    const t = document.createElement("canvas");
    t.width = c.width; t.height = c.height;
    const g = t.getContext("2d");
    g.drawImage(c, 0, 0);
    const d = g.getImageData(0, 0, t.width, t.height).data;
    const bg = [31, 35, 41];
    let all = 0, mid = 0, midTotal = 0, colours = new Set();
    for (let y = 0; y < t.height; y++)
      for (let x = 0; x < t.width; x++) {
        const i = 4 * (y * t.width + x);
        const part = Math.abs(d[i] - bg[0]) + Math.abs(d[i + 1] - bg[1]) + Math.abs(d[i + 2] - bg[2]) > 24;
        const inMid = Math.abs(x - t.width / 2) < t.width * 0.1 && Math.abs(y - t.height / 2) < t.height * 0.1;
        if (inMid) midTotal++;
        if (part) { all++; if (inMid) mid++; colours.add((d[i] >> 4) * 256 + (d[i + 1] >> 4) * 16 + (d[i + 2] >> 4)); }
      }
    return { w: t.width, h: t.height, all: all / (t.width * t.height), mid: mid / midTotal, colours: colours.size };
  })()`);
  check(px.w > 300 && px.h > 150, `the canvas has a size (${px.w} x ${px.h})`);
  check(px.all > 0.08, `the part covers the view (${(100 * px.all).toFixed(1)} % of the pixels)`);
  check(px.mid > 0.5, `the part fills the middle of the view (${(100 * px.mid).toFixed(1)} %)`);
  check(px.colours > 8, `the part is shaded and coloured (${px.colours} colours)`);
  // The toggles change the picture: the section plane, the ideal, the toolpath.
  const signature = `(() => {
    window.vpcutViewer.draw();
    const c = document.getElementById("view3d");
    const t = document.createElement("canvas");
    t.width = c.width; t.height = c.height;
    const g = t.getContext("2d");
    g.drawImage(c, 0, 0);
    const d = g.getImageData(0, 0, t.width, t.height).data;
    let h = 0;
    for (let i = 0; i < d.length; i += 4) h = (h * 31 + d[i] + 7 * d[i + 1] + 13 * d[i + 2]) >>> 0;
    return h;
  })()`;
  const toggle = (id) => evaluate(`(() => { const b = document.getElementById('${id}'); if (b.disabled) return false; b.click(); return true; })()`);
  const base = await evaluate(signature);
  for (const id of ["show-section", "show-ideal", "show-toolpath"]) {
    if (!(await toggle(id))) {
      console.log(`  --   ${id} is disabled (nothing to show)`);
      continue;
    }
    const changed = (await evaluate(signature)) !== base;
    await toggle(id);
    const back = (await evaluate(signature)) === base;
    check(changed && back, `${id} changes the picture and back`);
  }

  const shot = await s("Page.captureScreenshot", { format: "png", captureBeyondViewport: false });
  writeFileSync(page + ".png", Buffer.from(shot.data, "base64"));

  // The tables hold the report's numbers.
  const embedded = await evaluate("JSON.parse(document.getElementById('report-data').textContent)");
  check(
    embedded.verdict === report.verdict && embedded.findings.length === report.findings.length,
    "the embedded report is the run's report"
  );
  const tables = await evaluate(`(() => {
    const rows = (id) => Array.from(document.querySelectorAll('#' + id + ' tbody tr')).map((r) =>
      Array.from(r.cells).map((c) => c.hasAttribute('data-v') ? (c.getAttribute('data-v') === '' ? null : parseFloat(c.getAttribute('data-v'))) : c.textContent));
    return { turns: rows('turns'), findings: rows('findings'), verdict: document.getElementById('verdict').textContent };
  })()`);
  check(tables.verdict.startsWith(report.verdict.toUpperCase()), `the banner says ${report.verdict.toUpperCase()}`);
  check(tables.turns.length === report.turns.length, `a row per turn (${report.turns.length})`);
  let bad = [];
  report.turns.forEach((t, i) => {
    const r = tables.turns[i] || [];
    const want = [t.turn, t.start, t.ideal_lead_mm, t.measured_lead_mm, t.lead_spread.max_error_mm,
      t.ideal_groove_width_mm, t.groove_width_mm, t.ideal_tooth_width_mm, t.tooth_width_mm,
      t.min_diameter_mm, t.max_diameter_mm, t.helix_angle_deg, t.max_gouge_mm, t.max_leftover_mm,
      t.flanks.left.max_gouge_mm, t.flanks.left.max_leftover_mm, t.flanks.right.max_gouge_mm,
      t.flanks.right.max_leftover_mm, t.flanks.root.max_gouge_mm, t.flanks.root.max_leftover_mm,
      t.flanks.crest.max_gouge_mm, t.flanks.crest.max_leftover_mm, t.gouge_volume_mm3, t.leftover_volume_mm3];
    want.forEach((w, k) => { if ((w ?? null) !== r[k]) bad.push(`turn row ${i} column ${k}: ${r[k]} != ${w}`); });
  });
  check(bad.length === 0, `the turn rows hold the report's numbers ${bad.slice(0, 3).join("; ")}`);
  check(tables.findings.length === report.findings.length, `a row per finding (${report.findings.length})`);
  bad = [];
  report.findings.forEach((f, i) => {
    const r = tables.findings[i] || [];
    const want = [i + 1, f.severity, f.kind, f.turn, f.start, f.flank ?? "", f.angle_deg, f.z_mm, f.value ?? null, f.unit ?? ""];
    want.forEach((w, k) => { if ((w ?? null) !== r[k]) bad.push(`finding ${i} column ${k}: ${r[k]} != ${w}`); });
    if ((f.pass ?? null) !== r[10]) bad.push(`finding ${i}: pass ${r[10]} != ${f.pass}`);
    const source = f.file && f.line ? `${f.file}:${f.line}${f.column ? ":" + f.column : ""}` : (f.key ? `job key ${f.key}` : "");
    if (r[11] !== source) bad.push(`finding ${i}: source ${r[11]} != ${source}`);
    if (r[12] !== f.message) bad.push(`finding ${i}: message`);
  });
  check(bad.length === 0, `the finding rows hold the report's numbers ${bad.slice(0, 3).join("; ")}`);

  // A click on a finding flies the camera to it.
  const target = await evaluate(`(() => {
    const r = document.querySelector('#findings tbody tr[data-point]');
    if (!r) return null;
    r.scrollIntoView({block: 'center'});
    const b = r.cells[2].getBoundingClientRect();
    return { x: b.left + b.width / 2, y: b.top + b.height / 2, point: r.getAttribute('data-point').split(',').map(Number) };
  })()`);
  if (target) {
    const before = await evaluate("window.vpcutViewer.camera()");
    for (const type of ["mouseMoved", "mousePressed", "mouseReleased"]) {
      await s("Input.dispatchMouseEvent", { type, x: target.x, y: target.y, button: "left", clickCount: 1 });
    }
    await sleep(100);
    for (let t = 0; t < 100 && (await evaluate("window.vpcutViewer.flying")); t++) await sleep(100);
    const after = await evaluate("window.vpcutViewer.camera()");
    const moved = Math.hypot(...after.eye.map((e, i) => e - before.eye[i]));
    const onIt = Math.hypot(...after.target.map((e, i) => e - target.point[i]));
    check(moved > 1e-3 * before.dist, `clicking a finding moves the camera (eye moved ${moved.toFixed(3)} mm)`);
    check(onIt < 1e-3, `the camera looks at the finding (${onIt.toExponential(2)} mm off)`);
    check(after.dist < before.dist, `and closes in (distance ${before.dist.toFixed(1)} -> ${after.dist.toFixed(1)} mm)`);
    const box = await evaluate(`(() => { const c = document.getElementById('view3d'); c.scrollIntoView({block: 'center'}); const b = c.getBoundingClientRect(); return {x: b.left + window.scrollX, y: b.top + window.scrollY, width: b.width, height: b.height, scale: 1}; })()`);
    const close = await s("Page.captureScreenshot", { format: "png", clip: box });
    writeFileSync(page + ".finding.png", Buffer.from(close.data, "base64"));
  } else {
    check(report.findings.every((f) => f.angle_deg === null || f.z_mm === null), "no finding has a place to fly to");
  }

  // Sorting: the findings by value, ascending.
  if (report.findings.length > 1) {
    const sorted = await evaluate(`(() => {
      const th = document.querySelectorAll('#findings thead th')[8];
      th.click();
      const v = Array.from(document.querySelectorAll('#findings tbody tr')).map((r) => r.cells[8].getAttribute('data-v')).filter((x) => x !== '').map(Number);
      return v.every((x, i) => i === 0 || v[i - 1] <= x);
    })()`);
    check(sorted, "a click on a heading sorts the findings");
  }
  await sleep(200);
  check(errors.length === 0, `no console errors${errors.length ? ": " + errors.join(" | ") : ""}`);
  listeners.splice(listeners.indexOf(listener), 1);
  await send("Target.closeTarget", { targetId });
}

try {
  for (let i = 0; i < pairs.length; i += 2) await checkPage(pairs[i], pairs[i + 1]);
} catch (e) {
  console.error(e);
  console.error(stderr.slice(-2000));
  failures++;
} finally {
  try {
    await send("Browser.close");
  } catch (e) {
    proc.kill();
  }
}
console.log(failures === 0 ? "browser checks passed" : `${failures} browser check(s) failed`);
process.exit(failures === 0 ? 0 : 1);
