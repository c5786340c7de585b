// hier-fair's report viewer: WebGL 1, no library, no network. It reads the data of
// <script id="hf-data"> (made by hier_fair::html), draws the surfaces shaded by zebra stripes,
// curvature or deviation, their nets, knot lines, trims and curvature combs, and fills the link
// and surface tables. Licence: that of hier-fair (MIT OR Apache-2.0).
(function () {
  'use strict';
  var errors = [];
  function fail(msg) {
    errors.push(String(msg));
    document.body.setAttribute('data-errors', String(errors.length));
    var box = document.getElementById('hf-errors');
    if (box) box.textContent = errors.join('\n');
  }
  window.addEventListener('error', function (e) { fail(e.message); });
  var consoleError = console.error;
  console.error = function () {
    fail(Array.prototype.join.call(arguments, ' '));
    consoleError.apply(console, arguments);
  };

  var D = JSON.parse(document.getElementById('hf-data').textContent);
  var MM = D.mm_per_unit || 1;
  var NO_VALUE = 1e30; // stands for NaN in a vertex attribute (GLSL ES 1 cannot test NaN)

  function bytes(b64) {
    var s = atob(b64), out = new Uint8Array(s.length);
    for (var i = 0; i < s.length; i++) out[i] = s.charCodeAt(i);
    return out;
  }
  function floats(b64) { return new Float32Array(bytes(b64).buffer); }
  function fmt(x) {
    if (x === null || x === undefined || !isFinite(x)) return '–';
    if (x === 0) return '0';
    var a = Math.abs(x);
    if (a >= 0.01 && a < 10000) return String(Number(x.toPrecision(3)));
    var e = x.toExponential(2).replace('e+', 'e');
    return e;
  }

  // ---- 4×4 matrices, column-major as WebGL takes them
  function perspective(fovy, aspect, near, far) {
    var f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
    return [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0];
  }
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function unit(a) { var l = Math.sqrt(dot(a, a)) || 1; return [a[0] / l, a[1] / l, a[2] / l]; }
  function lookAt(eye, target, up) {
    var z = unit(sub(eye, target)), x = unit(cross(up, z)), y = cross(z, x);
    return [x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
      -dot(x, eye), -dot(y, eye), -dot(z, eye), 1];
  }
  function mul(a, b) {
    var o = new Array(16);
    for (var c = 0; c < 4; c++) for (var r = 0; r < 4; r++) {
      var s = 0;
      for (var k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
      o[c * 4 + r] = s;
    }
    return o;
  }

  // ---- WebGL set-up
  var canvas = document.getElementById('hf-canvas');
  var gl = canvas.getContext('webgl', { preserveDrawingBuffer: true, antialias: true });
  if (!gl) { fail('this browser has no WebGL: the 3D view cannot be shown (the tables below can)'); }
  var SURFACE_VS = [
    'attribute vec3 aPos; attribute vec3 aNrm; attribute float aVal;',
    'uniform mat4 uMV; uniform mat4 uP;',
    'varying vec3 vN; varying vec3 vE; varying float vVal;',
    'void main() { vec4 e = uMV * vec4(aPos, 1.0); vE = e.xyz; vN = (uMV * vec4(aNrm, 0.0)).xyz;',
    '  vVal = aVal; gl_Position = uP * e; }'].join('\n');
  var SURFACE_FS = [
    'precision highp float;',
    'varying vec3 vN; varying vec3 vE; varying float vVal;',
    'uniform int uMode; uniform float uStripes; uniform float uAngle; uniform vec2 uRange;',
    'uniform vec3 uTint; uniform float uTintAmount;',
    'vec3 diverging(float t) { vec3 b = vec3(0.23, 0.30, 0.75), w = vec3(0.97), r = vec3(0.71, 0.02, 0.15);',
    '  return t < 0.5 ? mix(b, w, t * 2.0) : mix(w, r, t * 2.0 - 1.0); }',
    'vec3 sequential(float t) { vec3 a = vec3(0.27, 0.0, 0.33), b = vec3(0.13, 0.57, 0.55), c = vec3(0.99, 0.91, 0.14);',
    '  return t < 0.5 ? mix(a, b, t * 2.0) : mix(b, c, t * 2.0 - 1.0); }',
    'void main() {',
    '  vec3 v = normalize(-vE); vec3 n = normalize(vN); if (dot(n, v) < 0.0) n = -n;',
    '  float light = 0.35 + 0.65 * abs(dot(n, v)); vec3 c;',
    '  if (uMode == 1) { vec3 r = reflect(-v, n); vec3 a = vec3(cos(uAngle), sin(uAngle), 0.0);',
    '    float s = asin(clamp(dot(r, a), -1.0, 1.0)) / 3.14159265 + 0.5;',
    '    c = vec3(mod(floor(s * uStripes), 2.0) < 0.5 ? 0.05 : 0.97); }',
    '  else if (uMode == 2 || uMode == 3) { if (abs(vVal) > 1e29) c = vec3(0.6) * light; else {',
    '    float t = clamp((vVal - uRange.x) / (uRange.y - uRange.x), 0.0, 1.0);',
    '    c = (uMode == 2 ? diverging(t) : sequential(t)) * (0.55 + 0.45 * light); } }',
    '  else c = vec3(0.78, 0.80, 0.84) * light;',
    '  gl_FragColor = vec4(mix(c, uTint, uTintAmount), 1.0); }'].join('\n');
  var LINE_VS = 'attribute vec3 aPos; uniform mat4 uMV; uniform mat4 uP; void main() { gl_Position = uP * uMV * vec4(aPos, 1.0); }';
  var LINE_FS = 'precision mediump float; uniform vec4 uColour; void main() { gl_FragColor = uColour; }';

  function program(vs, fs) {
    var p = gl.createProgram();
    [[gl.VERTEX_SHADER, vs], [gl.FRAGMENT_SHADER, fs]].forEach(function (s) {
      var sh = gl.createShader(s[0]);
      gl.shaderSource(sh, s[1]);
      gl.compileShader(sh);
      if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) fail('shader: ' + gl.getShaderInfoLog(sh));
      gl.attachShader(p, sh);
    });
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) fail('program: ' + gl.getProgramInfoLog(p));
    var info = { p: p, a: {}, u: {} };
    ['aPos', 'aNrm', 'aVal'].forEach(function (n) { info.a[n] = gl.getAttribLocation(p, n); });
    ['uMV', 'uP', 'uMode', 'uStripes', 'uAngle', 'uRange', 'uTint', 'uTintAmount', 'uColour']
      .forEach(function (n) { info.u[n] = gl.getUniformLocation(p, n); });
    return info;
  }
  function buffer(data, target) {
    var b = gl.createBuffer();
    gl.bindBuffer(target || gl.ARRAY_BUFFER, b);
    gl.bufferData(target || gl.ARRAY_BUFFER, data, gl.STATIC_DRAW);
    return b;
  }

  // ---- the model's geometry
  var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  D.surfaces.forEach(function (s) {
    var p = floats(s.before.grid.points);
    s.box = boxOf(p);
    for (var k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], s.box[0][k]); hi[k] = Math.max(hi[k], s.box[1][k]); }
  });
  function boxOf(p) {
    var a = [Infinity, Infinity, Infinity], b = [-Infinity, -Infinity, -Infinity];
    for (var i = 0; i + 2 < p.length; i += 3) for (var k = 0; k < 3; k++) {
      if (isFinite(p[i + k])) { a[k] = Math.min(a[k], p[i + k]); b[k] = Math.max(b[k], p[i + k]); }
    }
    return [a, b];
  }
  var centre = [(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2];
  var diag = Math.sqrt(dot(sub(hi, lo), sub(hi, lo))) || 1;
  function shifted(p) {
    var o = new Float32Array(p.length);
    for (var i = 0; i < p.length; i++) o[i] = p[i] - centre[i % 3];
    return o;
  }
  function noNaN(v) {
    var o = new Float32Array(v.length);
    for (var i = 0; i < v.length; i++) o[i] = isFinite(v[i]) ? v[i] : NO_VALUE;
    return o;
  }
  function polylineSegments(p, starts, lengths, closed) {
    var out = [];
    for (var l = 0; l < starts.length; l++) {
      var s = starts[l], n = lengths[l];
      for (var i = 0; i + 1 < n + (closed ? 1 : 0); i++) {
        var a = (s + i) * 3, b = (s + (i + 1) % n) * 3;
        out.push(p[a], p[a + 1], p[a + 2], p[b], p[b + 1], p[b + 2]);
      }
    }
    return new Float32Array(out);
  }

  function buildState(s, st) {
    var n = s.n, g = st.grid;
    var pos = shifted(floats(g.points));
    var idx = [];
    var cells = s.trim && s.trim.cells ? bytes(s.trim.cells) : null;
    for (var i = 0; i + 1 < n; i++) for (var j = 0; j + 1 < n; j++) {
      if (cells && !cells[i * (n - 1) + j]) continue;
      var a = i * n + j, b = a + n;
      idx.push(a, b, a + 1, a + 1, b, b + 1);
    }
    var fields = { mean: floats(g.mean), gauss: floats(g.gauss), k_u: floats(g.k_u), k_v: floats(g.k_v) };
    // the input lies on itself: its deviation is zero everywhere (shown as such, not as another field)
    fields.deviation = g.deviation ? floats(g.deviation) : new Float32Array(n * n);
    var out = {
      pos: pos, count: idx.length, fields: fields, normals: floats(g.normals), cells: cells,
      bPos: gl && buffer(pos), bNrm: gl && buffer(floats(g.normals)),
      bIdx: gl && buffer(new Uint16Array(idx), gl.ELEMENT_ARRAY_BUFFER), bVal: {}
    };
    // lines: the boundary (or the trim loops), the net, the knot lines
    var border = [], b4 = [[0, 1, n], [n * (n - 1), 1, n], [0, n, n], [n - 1, n, n]];
    b4.forEach(function (e) {
      for (var k = 0; k + 1 < e[2]; k++) {
        var a = (e[0] + k * e[1]) * 3, c = (e[0] + (k + 1) * e[1]) * 3;
        border.push(pos[a], pos[a + 1], pos[a + 2], pos[c], pos[c + 1], pos[c + 2]);
      }
    });
    out.edges = new Float32Array(border);
    if (s.trim) {
      var tp = shifted(floats(s.trim.loops)), starts = [], at = 0;
      s.trim.lengths.forEach(function (l) { starts.push(at); at += l; });
      var loops = polylineSegments(tp, starts, s.trim.lengths, true);
      out.edges = cells ? loops : concat(out.edges, loops);
    }
    var net = shifted(floats(st.net.points)), nu = st.net.size[0], nv = st.net.size[1], segs = [];
    for (var r = 0; r < nu; r++) for (var c2 = 0; c2 < nv; c2++) {
      var k0 = (r * nv + c2) * 3;
      if (c2 + 1 < nv) segs.push(net[k0], net[k0 + 1], net[k0 + 2], net[k0 + 3], net[k0 + 4], net[k0 + 5]);
      if (r + 1 < nu) { var k1 = k0 + nv * 3; segs.push(net[k0], net[k0 + 1], net[k0 + 2], net[k1], net[k1 + 1], net[k1 + 2]); }
    }
    out.net = new Float32Array(segs);
    out.knots = knotLines(pos, n, st.knots);
    ['edges', 'net', 'knots'].forEach(function (key) { out['b_' + key] = gl && buffer(out[key]); });
    return out;
  }
  // the iso-lines at the knots (shares of the domain) on the grid as drawn: between grid rows
  // i and i + 1 at share f, each line through every column
  function knotLines(pos, n, knots) {
    var out = [];
    function at(i, j) { return [pos[(i * n + j) * 3], pos[(i * n + j) * 3 + 1], pos[(i * n + j) * 3 + 2]]; }
    function lerp(a, b, f) { return [a[0] + f * (b[0] - a[0]), a[1] + f * (b[1] - a[1]), a[2] + f * (b[2] - a[2])]; }
    [['u', knots.u], ['v', knots.v]].forEach(function (d) {
      d[1].forEach(function (t) {
        var x = t * (n - 1), i = Math.min(n - 2, Math.floor(x)), f = x - i, prev = null;
        for (var j = 0; j < n; j++) {
          var p = d[0] === 'u' ? lerp(at(i, j), at(i + 1, j), f) : lerp(at(j, i), at(j, i + 1), f);
          if (prev) out.push(prev[0], prev[1], prev[2], p[0], p[1], p[2]);
          prev = p;
        }
      });
    });
    return new Float32Array(out);
  }
  function concat(a, b) { var o = new Float32Array(a.length + b.length); o.set(a); o.set(b, a.length); return o; }

  var hasAfter = D.kind === 'fair';
  D.surfaces.forEach(function (s) {
    s.gl = { before: buildState(s, s.before) };
    if (s.after) s.gl.after = buildState(s, s.after);
  });

  var MODES = { plain: 0, zebra: 1, mean: 2, gauss: 2, deviation: 3 };
  var MODES_LIST = Object.keys(MODES);
  // ---- view state
  var ui = {
    state: hasAfter ? 'after' : 'before', mode: 'zebra', stripes: 24, angle: Math.PI / 2,
    clamp: 1, net: false, knots: false, edges: true, combs: true, iso: '', isoAt: 0.5,
    combScale: 0, picked: -1, link: -1
  };
  // the view a link to the page asks for: #mode=mean&state=before&surface=NAME&link=K&clamp=2
  (location.hash || '').replace(/^#/, '').split('&').forEach(function (kv) {
    var p = kv.split('='), v = decodeURIComponent(p[1] || '');
    if (p[0] === 'mode' && MODES_LIST.indexOf(v) >= 0) ui.mode = v;
    if (p[0] === 'state' && (v === 'before' || (v === 'after' && hasAfter))) ui.state = v;
    if (p[0] === 'clamp' && isFinite(Number(v))) ui.clamp = Number(v);
    if (p[0] === 'stripes' && Number(v) > 0) ui.stripes = Number(v);
    if (p[0] === 'net') ui.net = v !== '0';
    if (p[0] === 'knots') ui.knots = v !== '0';
    if (p[0] === 'combs') ui.combs = v !== '0';
    if (p[0] === 'iso' && (v === 'u' || v === 'v')) ui.iso = v;
    if (p[0] === 'surface') D.surfaces.forEach(function (s, k) { if (s.name === v) ui.focusSurface = k; });
    if (p[0] === 'link' && D.links[Number(v)]) ui.focusLink = Number(v);
  });
  // the default stripe count: about 16 stripes across a view of `length` on a face of the
  // typical curvature κ (the 75th percentile of |H| over the curved samples of `surfaces`) —
  // the reflected ray turns by 2κ per unit length, and a stripe is 1/stripes of its half turn
  // (π). Set for the whole model at first, for a surface when the view focuses on it, until the
  // reader moves the slider.
  function autoStripes(surfaces, length) {
    if (ui.stripesSet) return;
    var flat = 1e-6 / diag, hs = [];
    surfaces.forEach(function (s) {
      var f = stateOf(s).fields.mean;
      for (var i = 0; i < f.length; i++) if (isFinite(f[i]) && Math.abs(f[i]) > flat) hs.push(Math.abs(f[i]));
    });
    if (!hs.length) return;
    hs.sort(function (a, b) { return a - b; });
    ui.stripes = Math.round(Math.max(4, Math.min(200, 8 * Math.PI / (quantile(hs, 0.75) * length))));
    var slider = document.getElementById('hf-stripes');
    if (slider) slider.value = ui.stripes;
  }
  ui.stripesSet = location.hash.indexOf('stripes=') >= 0;
  autoStripes(D.surfaces, diag);
  var cam = { target: [0, 0, 0], dist: 1.6 * diag, yaw: -0.9, pitch: 0.55, fov: 30 * Math.PI / 180 };
  function stateOf(s) { return s.gl[ui.state] || s.gl.before; }

  function fieldValues(name) {
    var out = [];
    D.surfaces.forEach(function (s) {
      var f = stateOf(s).fields[name];
      if (f) for (var i = 0; i < f.length; i++) if (isFinite(f[i])) out.push(f[i]);
    });
    return out;
  }
  function quantile(sorted, q) {
    if (!sorted.length) return 1;
    return sorted[Math.min(sorted.length - 1, Math.max(0, Math.floor(q * (sorted.length - 1))))];
  }
  function range() {
    var v = fieldValues(ui.mode);
    if (ui.mode === 'deviation') {
      v.sort(function (a, b) { return a - b; });
      return [0, quantile(v, 1 - ui.clamp / 100) || 1e-12];
    }
    var a = v.map(Math.abs).sort(function (x, y) { return x - y; });
    var h = quantile(a, 1 - ui.clamp / 100) || 1e-12;
    return [-h, h];
  }

  var surfaceProgram = gl && program(SURFACE_VS, SURFACE_FS);
  var lineProgram = gl && program(LINE_VS, LINE_FS);
  var currentRange = [-1, 1];

  function matrices() {
    var cp = Math.cos(cam.pitch);
    var dir = [cp * Math.cos(cam.yaw), cp * Math.sin(cam.yaw), Math.sin(cam.pitch)];
    var eye = [cam.target[0] + cam.dist * dir[0], cam.target[1] + cam.dist * dir[1], cam.target[2] + cam.dist * dir[2]];
    var aspect = canvas.width / canvas.height;
    return {
      mv: lookAt(eye, cam.target, [0, 0, 1]),
      p: perspective(cam.fov, aspect, cam.dist / 100, cam.dist * 4 + diag * 2),
      dir: dir
    };
  }

  function drawLines(data, buf, colour, m) {
    if (!data || !data.length) return;
    var P = lineProgram;
    gl.useProgram(P.p);
    gl.uniformMatrix4fv(P.u.uMV, false, m.mv);
    gl.uniformMatrix4fv(P.u.uP, false, m.p);
    gl.uniform4fv(P.u.uColour, colour);
    var b = buf || buffer(data);
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.enableVertexAttribArray(P.a.aPos);
    gl.vertexAttribPointer(P.a.aPos, 3, gl.FLOAT, false, 0, 0);
    gl.drawArrays(gl.LINES, 0, data.length / 3);
    if (!buf) gl.deleteBuffer(b);
  }

  function drawSurfaces(m) {
    var P = surfaceProgram;
    gl.useProgram(P.p);
    gl.uniformMatrix4fv(P.u.uMV, false, m.mv);
    gl.uniformMatrix4fv(P.u.uP, false, m.p);
    gl.uniform1i(P.u.uMode, MODES[ui.mode]);
    gl.uniform1f(P.u.uStripes, ui.stripes);
    gl.uniform1f(P.u.uAngle, ui.angle);
    gl.uniform2f(P.u.uRange, currentRange[0], currentRange[1]);
    D.surfaces.forEach(function (s, k) {
      var st = stateOf(s);
      if (!st.count) return;
      var field = st.fields[ui.mode] || st.fields.mean;
      var key = st.fields[ui.mode] ? ui.mode : 'mean';
      if (!st.bVal[key]) st.bVal[key] = buffer(noNaN(field));
      gl.uniform3f(P.u.uTint, 1.0, 0.62, 0.0);
      gl.uniform1f(P.u.uTintAmount, k === ui.picked ? 0.25 : 0.0);
      gl.bindBuffer(gl.ARRAY_BUFFER, st.bPos);
      gl.enableVertexAttribArray(P.a.aPos);
      gl.vertexAttribPointer(P.a.aPos, 3, gl.FLOAT, false, 0, 0);
      gl.bindBuffer(gl.ARRAY_BUFFER, st.bNrm);
      gl.enableVertexAttribArray(P.a.aNrm);
      gl.vertexAttribPointer(P.a.aNrm, 3, gl.FLOAT, false, 0, 0);
      gl.bindBuffer(gl.ARRAY_BUFFER, st.bVal[key]);
      gl.enableVertexAttribArray(P.a.aVal);
      gl.vertexAttribPointer(P.a.aVal, 1, gl.FLOAT, false, 0, 0);
      gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, st.bIdx);
      gl.drawElements(gl.TRIANGLES, st.count, gl.UNSIGNED_SHORT, 0);
    });
    gl.disableVertexAttribArray(P.a.aNrm);
    gl.disableVertexAttribArray(P.a.aVal);
  }

  // the typical tooth (that of the 95th percentile of the curvatures shown) as a share of the
  // model's diagonal: long enough to read a wiggle, short enough not to hide the surfaces
  var COMB_TOOTH = 0.025;
  // ---- combs: a tooth from each sample p to p − scale·κ·n (on the convex side), and the
  // envelope through the tips
  // the comb scale comes from the surfaces' curvature (the 95th percentile of the normal
  // curvatures along both iso-directions over the curved samples of every grid), not from the
  // combs' own: across a G2 join to a plane every comb is near zero and must stay drawn near
  // zero, and a part of many planes must not scale its fillets' combs by the planes' zeros
  function combScaleBase() {
    var flat = 1e-6 / diag;
    var ks = fieldValues('k_u').concat(fieldValues('k_v')).map(Math.abs)
      .filter(function (k) { return k > flat; }).sort(function (a, b) { return a - b; });
    return COMB_TOOTH * diag / (quantile(ks, 0.95) || 1 / diag);
  }
  var combBase = null;
  // a tooth longer than COMB_CAP × the comb's typical tooth (that of the 95th percentile) is
  // cut there, so that one spike does not hide the model; the table gives its figure
  var COMB_CAP = 1.5;
  function comb(points, normals, kappa, stride, scale) {
    var teeth = [], env = [], prev = null, cap = COMB_CAP * COMB_TOOTH * diag * Math.pow(2, ui.combScale);
    for (var i = 0; i * 3 < points.length; i++) {
      var k = kappa[i * stride] !== undefined ? kappa[i * stride] : kappa[i];
      if (!isFinite(k) || !isFinite(normals[i * 3])) { prev = null; continue; }
      var p = [points[i * 3] - centre[0], points[i * 3 + 1] - centre[1], points[i * 3 + 2] - centre[2]];
      var n = [normals[i * 3], normals[i * 3 + 1], normals[i * 3 + 2]];
      var len = Math.max(-cap, Math.min(cap, scale * k));
      var t = [p[0] - len * n[0], p[1] - len * n[1], p[2] - len * n[2]];
      teeth.push(p[0], p[1], p[2], t[0], t[1], t[2]);
      if (prev) env.push(prev[0], prev[1], prev[2], t[0], t[1], t[2]);
      prev = t;
    }
    return { teeth: new Float32Array(teeth), env: new Float32Array(env) };
  }
  function drawCombs(m) {
    if (combBase === null) combBase = combScaleBase();
    var scale = combBase * Math.pow(2, ui.combScale);
    gl.disable(gl.DEPTH_TEST);
    // a G0 link is a sharp edge: its curvatures across are not meant to agree, and it has none
    if (ui.combs) D.links.forEach(function (l, k) {
      if (ui.link >= 0 && k !== ui.link) return;
      if (l.target === 'G0' && k !== ui.link) return;
      var c = l['comb_' + ui.state] || l.comb_before;
      if (!c) return;
      // decoded once, not on every frame a drag draws
      if (!c.decoded) c.decoded = [floats(c.points), floats(c.normals), floats(c.slave), floats(c.master)];
      var p = c.decoded[0], n = c.decoded[1];
      var sl = comb(p, n, c.decoded[2], 1, scale), ma = comb(p, n, c.decoded[3], 1, scale);
      drawLines(sl.teeth, null, [0.84, 0.15, 0.16, 0.55], m);
      drawLines(sl.env, null, [0.84, 0.15, 0.16, 1], m);
      drawLines(ma.env, null, [0.12, 0.47, 0.71, 1], m);
    });
    var s = D.surfaces[ui.picked];
    if (ui.iso && s) {
      var st = stateOf(s), n2 = s.n, at = Math.round(ui.isoAt * (n2 - 1)), pts = [], nrm = [], ks = [];
      for (var i = 0; i < n2; i++) {
        var q = ui.iso === 'u' ? i * n2 + at : at * n2 + i;
        pts.push(st.pos[q * 3] + centre[0], st.pos[q * 3 + 1] + centre[1], st.pos[q * 3 + 2] + centre[2]);
        nrm.push(st.normals[q * 3], st.normals[q * 3 + 1], st.normals[q * 3 + 2]);
        ks.push(st.fields[ui.iso === 'u' ? 'k_u' : 'k_v'][q]);
      }
      var iso = comb(pts, nrm, ks, 1, scale);
      drawLines(iso.teeth, null, [0.1, 0.55, 0.2, 0.6], m);
      drawLines(iso.env, null, [0.1, 0.55, 0.2, 1], m);
    }
    gl.enable(gl.DEPTH_TEST);
  }

  function draw() {
    if (!gl) return;
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.clearColor(1, 1, 1, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
    var m = matrices();
    gl.enable(gl.POLYGON_OFFSET_FILL);
    gl.polygonOffset(1, 1);
    drawSurfaces(m);
    gl.disable(gl.POLYGON_OFFSET_FILL);
    D.surfaces.forEach(function (s, k) {
      var st = stateOf(s);
      if (ui.edges) drawLines(st.edges, st.b_edges, k === ui.picked ? [0.9, 0.45, 0, 1] : [0.95, 0.55, 0.1, 0.9], m);
      if (ui.knots) drawLines(st.knots, st.b_knots, [0.2, 0.2, 0.2, 0.55], m);
      if (ui.net) drawLines(st.net, st.b_net, [0.1, 0.3, 0.8, 0.8], m);
    });
    drawCombs(m);
    drawColourBar();
  }

  // ---- picking: the ray through the pixel against every triangle (a few hundred thousand at
  // most, run on a click only)
  function pick(x, y) {
    var m = matrices(), rect = canvas.getBoundingClientRect();
    var nx = 2 * (x - rect.left) / rect.width - 1, ny = 1 - 2 * (y - rect.top) / rect.height;
    var t = Math.tan(cam.fov / 2), aspect = canvas.width / canvas.height;
    var right = [m.mv[0], m.mv[4], m.mv[8]], up = [m.mv[1], m.mv[5], m.mv[9]], back = [m.mv[2], m.mv[6], m.mv[10]];
    var eye = [cam.target[0] + cam.dist * m.dir[0], cam.target[1] + cam.dist * m.dir[1], cam.target[2] + cam.dist * m.dir[2]];
    var d = unit([0, 1, 2].map(function (k) { return nx * t * aspect * right[k] + ny * t * up[k] - back[k]; }));
    var best = Infinity, which = -1;
    D.surfaces.forEach(function (s, k) {
      var st = stateOf(s), p = st.pos, n = s.n;
      for (var i = 0; i + 1 < n; i++) for (var j = 0; j + 1 < n; j++) {
        if (st.cells && !st.cells[i * (n - 1) + j]) continue;
        var a = i * n + j, q = [[a, a + n, a + 1], [a + 1, a + n, a + n + 1]];
        for (var h = 0; h < 2; h++) {
          var hit = ray(eye, d, p, q[h]);
          if (hit < best) { best = hit; which = k; }
        }
      }
    });
    return which;
  }
  function ray(o, d, p, tri) {
    var a = [p[tri[0] * 3], p[tri[0] * 3 + 1], p[tri[0] * 3 + 2]];
    var e1 = sub([p[tri[1] * 3], p[tri[1] * 3 + 1], p[tri[1] * 3 + 2]], a);
    var e2 = sub([p[tri[2] * 3], p[tri[2] * 3 + 1], p[tri[2] * 3 + 2]], a);
    var h = cross(d, e2), det = dot(e1, h);
    if (Math.abs(det) < 1e-20) return Infinity;
    var f = 1 / det, s = sub(o, a), u = f * dot(s, h);
    if (u < 0 || u > 1) return Infinity;
    var q = cross(s, e1), v = f * dot(d, q);
    if (v < 0 || u + v > 1) return Infinity;
    var t = f * dot(e2, q);
    return t > 0 ? t : Infinity;
  }
  // looks at surface k from outside: along its mean normal, turned to the side away from the
  // model's centre (a corner of a solid is seen from outside the solid)
  function lookFrom(k) {
    var st = stateOf(D.surfaces[k]), nr = st.normals, p = st.pos, m = [0, 0, 0], c = [0, 0, 0];
    for (var i = 0; i + 2 < nr.length; i += 3) for (var j = 0; j < 3; j++) { m[j] += nr[i + j]; c[j] += p[i + j]; }
    var out = unit(c), d = dot(m, m) > 1e-12 ? unit(m) : out;
    if (dot(d, out) < 0) d = [-d[0], -d[1], -d[2]];
    if (dot(c, c) < 1e-24 && dot(m, m) < 1e-12) return;
    cam.yaw = Math.atan2(d[1], d[0]);
    cam.pitch = Math.max(-1.4, Math.min(1.4, Math.asin(Math.max(-1, Math.min(1, d[2])))));
  }
  function focus(box) {
    var a = sub(box[0], centre), b = sub(box[1], centre);
    cam.target = [(a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2];
    var r = Math.max(0.5 * Math.sqrt(dot(sub(b, a), sub(b, a))), diag * 0.01);
    cam.dist = 1.15 * r / Math.sin(cam.fov / 2);
  }
  // the stripes for a view focused on surface k (its box's diagonal), by the curvature of `ks`
  function zoomStripes(ks, k) {
    var b = D.surfaces[k].box, d = sub(b[1], b[0]);
    autoStripes(ks.map(function (i) { return D.surfaces[i]; }), Math.sqrt(dot(d, d)) || diag);
  }
  function union(a, b) {
    return [[0, 1, 2].map(function (k) { return Math.min(a[0][k], b[0][k]); }),
      [0, 1, 2].map(function (k) { return Math.max(a[1][k], b[1][k]); })];
  }

  // ---- the colour bar of the curvature and deviation maps, in millimetre units
  function drawColourBar() {
    var bar = document.getElementById('hf-colourbar'), c = bar.getContext('2d');
    var shown = ui.mode === 'mean' || ui.mode === 'gauss' || ui.mode === 'deviation';
    bar.style.display = shown ? 'block' : 'none';
    if (!shown) return;
    var w = bar.width, x0 = 12, x1 = w - 12;
    c.clearRect(0, 0, w, bar.height);
    var g = c.createLinearGradient(x0, 0, x1, 0);
    var stops = ui.mode === 'deviation'
      ? [[0, '#450054'], [0.5, '#21918c'], [1, '#fde725']] : [[0, '#3b4cc0'], [0.5, '#f7f7f7'], [1, '#b40426']];
    stops.forEach(function (s) { g.addColorStop(s[0], s[1]); });
    c.fillStyle = g;
    c.fillRect(x0, 20, x1 - x0, 12);
    c.strokeStyle = '#333';
    c.strokeRect(x0, 20, x1 - x0, 12);
    var unitScale = ui.mode === 'deviation' ? MM : ui.mode === 'gauss' ? 1 / (MM * MM) : 1 / MM;
    var unitText = ui.mode === 'deviation' ? 'mm' : ui.mode === 'gauss' ? '1/mm²' : '1/mm';
    var title = { mean: 'mean curvature', gauss: 'Gaussian curvature', deviation: 'deviation from the input' }[ui.mode];
    c.fillStyle = '#111';
    c.font = '12px sans-serif';
    c.textAlign = 'left';
    c.fillText(title + ' (' + unitText + '), ' + ui.state + (ui.clamp > 0 ? ', top ' + ui.clamp + ' % clamped' : ''), x0, 13);
    c.textAlign = 'center';
    [0, 0.5, 1].forEach(function (t) {
      var v = (currentRange[0] + t * (currentRange[1] - currentRange[0])) * unitScale;
      var label = (t === 0 && ui.mode !== 'deviation' ? '≤ ' : t === 1 ? '≥ ' : '') + fmt(v);
      c.fillText(label, Math.min(Math.max(x0 + t * (x1 - x0), 30), w - 30), 48);
    });
  }

  function redraw() {
    if (ui.mode !== 'plain' && ui.mode !== 'zebra') currentRange = range();
    draw();
  }

  // ---- mouse
  var drag = null;
  canvas.addEventListener('contextmenu', function (e) { e.preventDefault(); });
  canvas.addEventListener('pointerdown', function (e) {
    drag = { x: e.clientX, y: e.clientY, moved: 0, pan: e.shiftKey || e.button === 2 };
    canvas.setPointerCapture(e.pointerId);
  });
  canvas.addEventListener('pointermove', function (e) {
    if (!drag) return;
    var dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY; drag.moved += Math.abs(dx) + Math.abs(dy);
    if (drag.pan) {
      var m = matrices(), k = cam.dist * 2 * Math.tan(cam.fov / 2) / canvas.clientHeight;
      for (var i = 0; i < 3; i++) cam.target[i] += k * (-dx * m.mv[i * 4] + dy * m.mv[i * 4 + 1]);
    } else {
      cam.yaw -= dx * 0.01;
      cam.pitch = Math.max(-1.55, Math.min(1.55, cam.pitch + dy * 0.01));
    }
    draw();
  });
  canvas.addEventListener('pointerup', function (e) {
    if (drag && drag.moved < 4) select(pick(e.clientX, e.clientY), -1, false);
    drag = null;
  });
  canvas.addEventListener('wheel', function (e) {
    e.preventDefault();
    cam.dist *= Math.exp(e.deltaY * 0.0015);
    draw();
  }, { passive: false });

  function select(surface, link, zoom) {
    ui.picked = surface;
    ui.link = link;
    var box = null;
    if (link >= 0) {
      var l = D.links[link];
      box = union(D.surfaces[l.slave].box, D.surfaces[l.master].box);
      if (zoom) { lookFrom(l.slave); focus(D.surfaces[l.slave].box); zoomStripes([l.slave, l.master], l.slave); }
    } else if (surface >= 0 && zoom) {
      lookFrom(surface);
      focus(D.surfaces[surface].box);
      zoomStripes([surface], surface);
    }
    var text = '';
    if (surface >= 0) {
      var s = D.surfaces[surface], st = s[ui.state] || s.before;
      text = s.name + ' (' + s.role + ')\ndegree ' + st.degree.join(' × ') + ', net ' + st.net.size.join(' × ');
    }
    if (link >= 0) text += (text ? '\n' : '') + 'link ' + D.links[link].label;
    document.getElementById('hf-picked').textContent = text || 'nothing picked';
    markRows();
    redraw();
    return box;
  }
  window.hierFair = { data: D, select: select, camera: cam, ui: ui, redraw: redraw };
  hierFairTables(D, MM, fmt, select);

  function markRows() {
    document.querySelectorAll('#hf-links tbody tr').forEach(function (tr) {
      tr.className = Number(tr.dataset.index) === ui.link ? 'sel' : '';
    });
    document.querySelectorAll('#hf-surfaces tbody tr').forEach(function (tr) {
      tr.className = Number(tr.dataset.index) === ui.picked ? 'sel' : '';
    });
  }

  // ---- controls
  function bind(id, event, f) { document.getElementById(id).addEventListener(event, function (e) { f(e.target); redraw(); }); }
  document.querySelectorAll('input[name=state]').forEach(function (r) {
    if (!hasAfter) r.disabled = true;
    r.checked = r.value === ui.state;
    r.addEventListener('change', function () { ui.state = r.value; combBase = null; redraw(); });
  });
  if (!hasAfter) document.querySelector('#hf-mode option[value=deviation]').disabled = true;
  bind('hf-mode', 'change', function (t) { ui.mode = t.value; });
  bind('hf-stripes', 'input', function (t) { ui.stripes = Number(t.value); ui.stripesSet = true; });
  bind('hf-angle', 'input', function (t) { ui.angle = Number(t.value) * Math.PI / 180; });
  bind('hf-clamp', 'input', function (t) { ui.clamp = Number(t.value); clampText(); });
  bind('hf-net', 'change', function (t) { ui.net = t.checked; });
  bind('hf-knots', 'change', function (t) { ui.knots = t.checked; });
  bind('hf-edges', 'change', function (t) { ui.edges = t.checked; });
  bind('hf-combs', 'change', function (t) { ui.combs = t.checked; });
  bind('hf-iso', 'change', function (t) { ui.iso = t.value; if (ui.picked < 0) ui.picked = 0; });
  bind('hf-iso-at', 'input', function (t) { ui.isoAt = Number(t.value) / 1000; });
  bind('hf-comb-scale', 'input', function (t) { ui.combScale = Number(t.value); });
  document.getElementById('hf-mode').value = ui.mode;
  document.getElementById('hf-clamp').value = ui.clamp;
  document.getElementById('hf-stripes').value = ui.stripes;
  document.getElementById('hf-net').checked = ui.net;
  document.getElementById('hf-knots').checked = ui.knots;
  document.getElementById('hf-combs').checked = ui.combs;
  document.getElementById('hf-iso').value = ui.iso;
  function clampText() { document.getElementById('hf-clamp-text').textContent = ui.clamp + ' %'; }
  clampText();

  function resize() {
    var w = Math.max(320, Math.round(canvas.clientWidth * (window.devicePixelRatio || 1)));
    canvas.width = w;
    canvas.height = Math.round(w * 2 / 3);
    draw();
  }
  window.addEventListener('resize', resize);
  document.getElementById('hf-footer').textContent = 'Made by ' + D.generator + ' — ' + D.surfaces.length +
    ' surfaces, ' + D.links.length + ' links; lengths shown in millimetres (the model\'s unit: ' + D.unit + ').';
  resize();
  if (ui.focusLink !== undefined) select(D.links[ui.focusLink].slave, ui.focusLink, true);
  else if (ui.focusSurface !== undefined) select(ui.focusSurface, -1, true);
  else redraw();

  // the page's own account of its first frame, for readers and for tests: how many pixels are
  // not the background
  if (gl) {
    var px = new Uint8Array(canvas.width * canvas.height * 4), drawn = 0;
    gl.readPixels(0, 0, canvas.width, canvas.height, gl.RGBA, gl.UNSIGNED_BYTE, px);
    for (var i = 0; i < px.length; i += 4) if (px[i] < 250 || px[i + 1] < 250 || px[i + 2] < 250) drawn++;
    document.body.setAttribute('data-drawn-pixels', String(drawn));
  }
  document.body.setAttribute('data-rendered', 'yes');
})();
