"use strict";
// vpcut's 3D view: a small WebGL2 viewer of the scene embedded in the page (flat arrays in
// base64, see output/html.rs). The cut part's triangles carry the deviation colours; the
// ideal thread is a translucent sheet and the toolpath line strips. Orbit, pan, zoom, a
// section plane through the axis, and a fly-to for the findings' rows.
// The state is exposed as window.vpcutViewer for the page's browser test.
(function () {
  const status = document.getElementById("view-status");
  const canvas = document.getElementById("view3d");
  const viewer = { ready: false, error: null, frames: 0, flying: false };
  window.vpcutViewer = viewer;
  function fail(msg) {
    viewer.error = msg;
    if (status) status.textContent = msg;
  }
  const hdr = JSON.parse(document.getElementById("scene-header").textContent);
  const text = atob(document.getElementById("scene-data").textContent.trim());
  const bin = new Uint8Array(text.length);
  for (let i = 0; i < text.length; i++) bin[i] = text.charCodeAt(i);
  const buf = bin.buffer;

  const gl = canvas.getContext("webgl2", { antialias: true, preserveDrawingBuffer: true });
  if (!gl) {
    fail("This browser has no WebGL2: the 3D view is not available.");
    return;
  }

  function shader(type, src) {
    const s = gl.createShader(type);
    gl.shaderSource(s, src);
    gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    return s;
  }
  function program(vs, fs) {
    const p = gl.createProgram();
    gl.attachShader(p, shader(gl.VERTEX_SHADER, vs));
    gl.attachShader(p, shader(gl.FRAGMENT_SHADER, fs));
    gl.bindAttribLocation(p, 0, "pos");
    gl.bindAttribLocation(p, 1, "col");
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(p));
    const u = {};
    const n = gl.getProgramParameter(p, gl.ACTIVE_UNIFORMS);
    for (let i = 0; i < n; i++) {
      const name = gl.getActiveUniform(p, i).name;
      u[name] = gl.getUniformLocation(p, name);
    }
    return { p: p, u: u };
  }

  const meshProg = program(
    "#version 300 es\n" +
      "layout(location=0) in vec3 pos; layout(location=1) in vec3 col;\n" +
      "uniform mat4 mvp; out vec3 vpos; out vec3 vcol;\n" +
      "void main() { vpos = pos; vcol = col; gl_Position = mvp * vec4(pos, 1.0); }\n",
    "#version 300 es\nprecision highp float;\n" +
      "in vec3 vpos; in vec3 vcol; uniform vec4 plane; uniform int clip; uniform vec3 eye;\n" +
      "uniform float alpha; uniform int sheet; out vec4 o;\n" +
      "void main() {\n" +
      "  if (clip == 1 && dot(plane.xyz, vpos) > plane.w) discard;\n" +
      "  vec3 n = normalize(cross(dFdx(vpos), dFdy(vpos)));\n" +
      "  vec3 v = normalize(eye - vpos);\n" +
      "  float l = min(1.15, 0.45 + 0.8 * abs(dot(n, v)));\n" +
      "  vec3 c = vcol;\n" +
      "  if (sheet == 0 && !gl_FrontFacing) c = vec3(0.42, 0.40, 0.38);\n" +
      "  o = vec4(c * l, alpha);\n" +
      "}\n"
  );
  const lineProg = program(
    "#version 300 es\nlayout(location=0) in vec3 pos; uniform mat4 mvp; out vec3 vpos;\n" +
      "void main() { vpos = pos; gl_Position = mvp * vec4(pos, 1.0); }\n",
    "#version 300 es\nprecision highp float;\n" +
      "in vec3 vpos; uniform vec4 plane; uniform int clip; uniform vec4 colour; out vec4 o;\n" +
      "void main() { if (clip == 1 && dot(plane.xyz, vpos) > plane.w) discard; o = colour; }\n"
  );

  function meshVao(m) {
    if (!m || m.ni === 0) return null;
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const pb = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, pb);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(buf, m.pos, m.n * 3), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
    const cb = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, cb);
    gl.bufferData(gl.ARRAY_BUFFER, new Uint8Array(buf, m.col, m.n * 3), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(1);
    gl.vertexAttribPointer(1, 3, gl.UNSIGNED_BYTE, true, 0, 0);
    const ib = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib);
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, new Uint32Array(buf, m.idx, m.ni), gl.STATIC_DRAW);
    gl.bindVertexArray(null);
    return { vao: vao, count: m.ni };
  }
  const stock = meshVao(hdr.stock);
  const ideal = meshVao(hdr.ideal);
  let lines = null;
  if (hdr.lines.n > 0) {
    const vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    const b = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(buf, hdr.lines.pos, hdr.lines.n * 3), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
    gl.bindVertexArray(null);
    lines = vao;
  }
  // A marker: three short axis lines, scaled about the selected point.
  const marker = gl.createVertexArray();
  const markerBuf = gl.createBuffer();
  gl.bindVertexArray(marker);
  gl.bindBuffer(gl.ARRAY_BUFFER, markerBuf);
  gl.bufferData(gl.ARRAY_BUFFER, 18 * 4, gl.DYNAMIC_DRAW);
  gl.enableVertexAttribArray(0);
  gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
  gl.bindVertexArray(null);

  const ideal_box = document.getElementById("show-ideal");
  const path_box = document.getElementById("show-toolpath");
  const section_box = document.getElementById("show-section");
  const angle_in = document.getElementById("section-angle");
  const offset_in = document.getElementById("section-offset");
  if (!ideal) {
    ideal_box.disabled = true;
    ideal_box.parentNode.title = "no ideal surface in this report";
  }
  if (!lines) path_box.disabled = true;
  // The renders' rule: a toolpath that would hide the part starts faint or off.
  const pathLook = hdr.toolpath ? hdr.toolpath.look : "full";
  const pathAlpha = pathLook === "dimmed" ? 0.3 : 1;
  if (pathLook === "hidden") path_box.checked = false;
  if (pathLook !== "full" && hdr.toolpath) {
    path_box.parentNode.title =
      "starts " + (pathLook === "hidden" ? "off" : "faint") + ": its lines cross " +
      Math.round(100 * hdr.toolpath.coverage) + " % of the part in the iso view";
  }
  // An internal thread starts in section, so the bore shows.
  if (hdr.internal) section_box.checked = true;

  // The part's bounds and the camera framing it.
  const lo = hdr.bounds ? hdr.bounds[0] : [-1, -1, -1];
  const hi = hdr.bounds ? hdr.bounds[1] : [1, 1, 1];
  const centre = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2];
  const radius = Math.max(1e-3, 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]));
  const partRadius = Math.max(1e-3, Math.max(Math.abs(lo[0]), Math.abs(hi[0]), Math.abs(lo[1]), Math.abs(hi[1])));
  const fov = (35 * Math.PI) / 180;
  const home = { target: centre.slice(), dist: (1.1 * radius) / Math.sin(fov / 2), yaw: 1.1, pitch: 0.45 };
  const cam = { target: home.target.slice(), dist: home.dist, yaw: home.yaw, pitch: home.pitch };
  let selected = null;

  function eye() {
    const cp = Math.cos(cam.pitch);
    return [
      cam.target[0] + cam.dist * cp * Math.sin(cam.yaw),
      cam.target[1] + cam.dist * Math.sin(cam.pitch),
      cam.target[2] + cam.dist * cp * Math.cos(cam.yaw),
    ];
  }
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function norm(a) { const l = Math.hypot(a[0], a[1], a[2]) || 1; return [a[0] / l, a[1] / l, a[2] / l]; }
  function basis() {
    const e = eye();
    const f = norm(sub(cam.target, e));
    const r = norm(cross(f, [0, 1, 0]));
    const u = cross(r, f);
    return { e: e, f: f, r: r, u: u };
  }
  function matrix(aspect) {
    const b = basis();
    const near = Math.max(cam.dist - 1.5 * radius, cam.dist * 0.002);
    const far = cam.dist + 2.5 * radius;
    const t = 1 / Math.tan(fov / 2);
    // view (row vectors r, u, -f) then perspective; column-major.
    const v = [
      b.r[0], b.u[0], -b.f[0], 0,
      b.r[1], b.u[1], -b.f[1], 0,
      b.r[2], b.u[2], -b.f[2], 0,
      -dot(b.r, b.e), -dot(b.u, b.e), dot(b.f, b.e), 1,
    ];
    const p = [
      t / aspect, 0, 0, 0,
      0, t, 0, 0,
      0, 0, (far + near) / (near - far), -1,
      0, 0, (2 * far * near) / (near - far), 0,
    ];
    const m = new Float32Array(16);
    for (let c = 0; c < 4; c++)
      for (let r = 0; r < 4; r++) {
        let s = 0;
        for (let k = 0; k < 4; k++) s += p[k * 4 + r] * v[c * 4 + k];
        m[c * 4 + r] = s;
      }
    return { m: m, e: b.e };
  }

  let pending = false;
  function redraw() {
    if (!pending) {
      pending = true;
      requestAnimationFrame(draw);
    }
  }
  function draw() {
    pending = false;
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(canvas.clientWidth * dpr));
    const h = Math.max(1, Math.round(canvas.clientHeight * dpr));
    if (canvas.width !== w || canvas.height !== h) {
      canvas.width = w;
      canvas.height = h;
    }
    gl.viewport(0, 0, w, h);
    gl.clearColor(0.122, 0.137, 0.161, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    const mv = matrix(w / h);
    const a = (Number(angle_in.value) * Math.PI) / 180;
    const plane = [Math.cos(a), Math.sin(a), 0, Number(offset_in.value) * partRadius];
    const clip = section_box.checked ? 1 : 0;

    gl.useProgram(meshProg.p);
    gl.uniformMatrix4fv(meshProg.u.mvp, false, mv.m);
    gl.uniform4fv(meshProg.u.plane, plane);
    gl.uniform1i(meshProg.u.clip, clip);
    gl.uniform3fv(meshProg.u.eye, mv.e);
    gl.uniform1f(meshProg.u.alpha, 1);
    gl.uniform1i(meshProg.u.sheet, 0);
    gl.disable(gl.BLEND);
    gl.depthMask(true);
    if (stock) {
      gl.bindVertexArray(stock.vao);
      gl.drawElements(gl.TRIANGLES, stock.count, gl.UNSIGNED_INT, 0);
    }
    gl.useProgram(lineProg.p);
    gl.uniformMatrix4fv(lineProg.u.mvp, false, mv.m);
    gl.uniform4fv(lineProg.u.plane, plane);
    gl.uniform1i(lineProg.u.clip, 0);
    if (lines && path_box.checked) {
      gl.bindVertexArray(lines);
      if (pathAlpha < 1) {
        gl.enable(gl.BLEND);
        gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
      }
      for (const s of hdr.lines.strips) {
        gl.uniform4fv(lineProg.u.colour, s[2] === 0 ? [0.39, 0.69, 0, pathAlpha] : [0.55, 0.6, 0.7, pathAlpha]);
        gl.drawArrays(gl.LINE_STRIP, s[0], s[1]);
      }
      gl.disable(gl.BLEND);
    }
    if (selected) {
      const k = cam.dist * 0.04;
      const p = selected;
      const pts = new Float32Array([
        p[0] - k, p[1], p[2], p[0] + k, p[1], p[2],
        p[0], p[1] - k, p[2], p[0], p[1] + k, p[2],
        p[0], p[1], p[2] - k, p[0], p[1], p[2] + k,
      ]);
      gl.bindBuffer(gl.ARRAY_BUFFER, markerBuf);
      gl.bufferSubData(gl.ARRAY_BUFFER, 0, pts);
      gl.bindVertexArray(marker);
      gl.disable(gl.DEPTH_TEST);
      gl.uniform4fv(lineProg.u.colour, [1, 1, 0.3, 1]);
      gl.drawArrays(gl.LINES, 0, 6);
      gl.enable(gl.DEPTH_TEST);
    }
    if (ideal && ideal_box.checked) {
      gl.useProgram(meshProg.p);
      gl.uniform1f(meshProg.u.alpha, 0.35);
      gl.uniform1i(meshProg.u.sheet, 1);
      gl.enable(gl.BLEND);
      gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
      gl.depthMask(false);
      gl.bindVertexArray(ideal.vao);
      gl.drawElements(gl.TRIANGLES, ideal.count, gl.UNSIGNED_INT, 0);
      gl.depthMask(true);
      gl.disable(gl.BLEND);
    }
    gl.bindVertexArray(null);
    viewer.frames++;
  }

  // Orbit, pan, zoom.
  let drag = null;
  canvas.addEventListener("contextmenu", function (e) { e.preventDefault(); });
  canvas.addEventListener("pointerdown", function (e) {
    drag = { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.shiftKey };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener("pointerup", function () { drag = null; });
  canvas.addEventListener("pointermove", function (e) {
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (drag.pan) {
      const b = basis();
      const s = (2 * cam.dist * Math.tan(fov / 2)) / Math.max(1, canvas.clientHeight);
      for (let i = 0; i < 3; i++) cam.target[i] += (-dx * b.r[i] + dy * b.u[i]) * s;
    } else {
      cam.yaw -= dx * 0.008;
      cam.pitch = Math.max(-1.5, Math.min(1.5, cam.pitch + dy * 0.008));
    }
    redraw();
  });
  canvas.addEventListener("wheel", function (e) {
    e.preventDefault();
    cam.dist = Math.max(radius * 0.005, Math.min(radius * 20, cam.dist * Math.exp(e.deltaY * 0.001)));
    redraw();
  }, { passive: false });
  for (const el of [ideal_box, path_box, section_box, angle_in, offset_in]) el.addEventListener("input", redraw);
  window.addEventListener("resize", redraw);

  // Flying to a place.
  function flyTo(goal, ms) {
    const from = { target: cam.target.slice(), dist: cam.dist, yaw: cam.yaw, pitch: cam.pitch };
    let dyaw = goal.yaw - from.yaw;
    dyaw -= 2 * Math.PI * Math.round(dyaw / (2 * Math.PI));
    const t0 = performance.now();
    viewer.flying = true;
    function step(now) {
      const t = Math.min(1, (now - t0) / ms);
      const s = t * t * (3 - 2 * t);
      for (let i = 0; i < 3; i++) cam.target[i] = from.target[i] + s * (goal.target[i] - from.target[i]);
      cam.dist = from.dist * Math.pow(goal.dist / from.dist, s);
      cam.yaw = from.yaw + s * dyaw;
      cam.pitch = from.pitch + s * (goal.pitch - from.pitch);
      draw();
      if (t < 1) requestAnimationFrame(step);
      else viewer.flying = false;
    }
    requestAnimationFrame(step);
  }
  function flyToPoint(p) {
    selected = p;
    // Look at the point from outside the part, radially, a little along the axis.
    const d = norm([p[0], p[1], 0.35 * Math.hypot(p[0], p[1])]);
    flyTo({
      target: p.slice(),
      dist: Math.max(radius * 0.02, partRadius * 0.6) / Math.sin(fov / 2),
      yaw: Math.atan2(d[0], d[2]),
      pitch: Math.max(-1.5, Math.min(1.5, Math.asin(d[1]))),
    }, 700);
  }
  document.getElementById("view-reset").addEventListener("click", function () {
    selected = null;
    flyTo(home, 400);
  });
  const rows = document.querySelectorAll("#findings tbody tr");
  for (const row of rows) {
    row.addEventListener("click", function () {
      for (const r of rows) r.classList.remove("selected");
      row.classList.add("selected");
      const a = row.getAttribute("data-point");
      if (!a) return;
      flyToPoint(a.split(",").map(Number));
      canvas.scrollIntoView({ behavior: "smooth", block: "center" });
    });
  }

  viewer.camera = function () {
    return { target: cam.target.slice(), dist: cam.dist, yaw: cam.yaw, pitch: cam.pitch, eye: eye() };
  };
  viewer.home = home;
  viewer.flyToPoint = flyToPoint;
  viewer.draw = draw;
  draw();
  viewer.ready = true;
})();
