// SPDX-License-Identifier: MIT
// The player of `sfit skeleton --html`: a 3-D view of the skeleton over
// the markers, orthographic, orbit / zoom / pan with the mouse or touch,
// a floor grid and a scale bar, each joint's 95 % ellipsoid. Plain
// script, no library: the page needs nothing but itself. The data object
// D is written before this script by skel_draw.c (skel_write_html).
'use strict';
const cv = document.getElementById('cv'), cx = cv.getContext('2d');
const S = D.seg.length, NM = D.mseg.length, NF = D.f.length;
const frIn = document.getElementById('fr'), info = document.getElementById('info');
const ellSel = document.getElementById('ell');
// Lab axes to a right-handed frame whose third axis points up.
const upAx = D.up, hA = (D.up + 1) % 3, hB = (D.up + 2) % 3;
const ax0 = D.sgn > 0 ? hA : hB, ax1 = D.sgn > 0 ? hB : hA;
function can(p) { return [p[ax0], p[ax1], D.sgn * p[upAx]]; }
function pt(row, i) { return row[3 * i] === null ? null : can([row[3 * i], row[3 * i + 1], row[3 * i + 2]]); }
// Fixed target and extent over the whole recording (the camera does not
// follow the subject: the floor grid shows where it goes).
let tgt = [0, 0, 0], ext = 1, floorZ = 0;
(function () {
  const xs = [[], [], []];
  for (const row of D.f) {
    for (let i = 0; i < row.length / 3; i++) {
      if (i >= 2 * S + NM) break;
      const p = pt(row, i);
      if (p) for (let a = 0; a < 3; a++) xs[a].push(p[a]);
    }
  }
  const q = (v, f) => { if (!v.length) return 0; const s = v.slice().sort((a, b) => a - b); return s[Math.floor(f * (s.length - 1))]; };
  for (let a = 0; a < 3; a++) tgt[a] = 0.5 * (q(xs[a], 0.005) + q(xs[a], 0.995));
  let e = 0;
  for (let a = 0; a < 3; a++) e = Math.max(e, q(xs[a], 0.995) - q(xs[a], 0.005));
  ext = Math.max(e, 1e-9);
  floorZ = q(xs[2], 0.005);
})();
function nice(x) { const k = Math.pow(10, Math.floor(Math.log10(x))), m = x / k; return (m < 1.5 ? 1 : m < 3.5 ? 2 : m < 7.5 ? 5 : 10) * k; }
const grid = nice(ext / 6);
const V = { yaw: -0.6, pitch: 0.35, zoom: 1, pan: [0, 0] };
const V0 = Object.assign({}, V, { pan: [0, 0] });
function basis() {
  const cy = Math.cos(V.yaw), sy = Math.sin(V.yaw), cp = Math.cos(V.pitch), sp = Math.sin(V.pitch);
  const right = [cy, sy, 0], fh = [-sy, cy, 0];
  return { right: right, up: [sp * fh[0], sp * fh[1], cp], fwd: [cp * fh[0], cp * fh[1], -sp] };
}
let B = basis(), SC = 1;
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
function proj(p) {
  const d = [p[0] - tgt[0], p[1] - tgt[1], p[2] - tgt[2]];
  return [cv.width / 2 + V.pan[0] + dot(d, B.right) * SC, cv.height / 2 + V.pan[1] - dot(d, B.up) * SC, dot(d, B.fwd)];
}
// Screen ellipse of a covariance (canonical axes, packed xx yy zz xy xz yz).
function ellipse(c) {
  const M = [[c[0], c[3], c[4]], [c[3], c[1], c[5]], [c[4], c[5], c[2]]];
  const r = B.right, u = B.up;
  const mv = (v) => [dot(M[0], v), dot(M[1], v), dot(M[2], v)];
  const a = dot(r, mv(r)), b = dot(r, mv(u)), d = dot(u, mv(u));
  const t = 0.5 * (a + d), s = Math.sqrt(Math.max(0, 0.25 * (a - d) * (a - d) + b * b));
  return [Math.sqrt(Math.max(0, t + s)), Math.sqrt(Math.max(0, t - s)), 0.5 * Math.atan2(2 * b, a - d)];
}
function trialOf(k) {
  const f = k * D.stride;
  let t = 0;
  for (let i = 0; i < D.trials.length; i++) if (D.trials[i].start <= f) t = i;
  return t;
}
let cur = 0, timer = null;
function drawGrid() {
  const n = Math.ceil(0.75 * ext / grid) + 1;
  const gx = Math.round(tgt[0] / grid) * grid, gy = Math.round(tgt[1] / grid) * grid;
  cx.lineWidth = 1;
  for (let i = -n; i <= n; i++) {
    cx.strokeStyle = i === 0 ? '#b8b8b8' : '#e2e2e2';
    let a = proj([gx + i * grid, gy - n * grid, floorZ]), b = proj([gx + i * grid, gy + n * grid, floorZ]);
    cx.beginPath(); cx.moveTo(a[0], a[1]); cx.lineTo(b[0], b[1]); cx.stroke();
    a = proj([gx - n * grid, gy + i * grid, floorZ]); b = proj([gx + n * grid, gy + i * grid, floorZ]);
    cx.beginPath(); cx.moveTo(a[0], a[1]); cx.lineTo(b[0], b[1]); cx.stroke();
  }
}
function drawScale() {
  const len = nice(110 / SC), px = len * SC, x = 16, y = cv.height - 18;
  cx.strokeStyle = '#222'; cx.lineWidth = 3;
  cx.beginPath(); cx.moveTo(x, y); cx.lineTo(x + px, y); cx.moveTo(x, y - 5); cx.lineTo(x, y + 5);
  cx.moveTo(x + px, y - 5); cx.lineTo(x + px, y + 5); cx.stroke();
  cx.fillStyle = '#222'; cx.font = '12px sans-serif';
  cx.fillText(len + ' ' + D.units + ' (grid ' + grid + ' ' + D.units + ')', x, y - 9);
  // the lab axes
  const o = [cv.width - 60, cv.height - 50], names = ['x', 'y', 'z'], col = ['#c0392b', '#1b9e4b', '#2a6fdb'];
  for (let a = 0; a < 3; a++) {
    const e = [0, 0, 0]; e[a] = 1; const c = can(e);
    const sx = dot(c, B.right) * 30, sy = -dot(c, B.up) * 30;
    cx.strokeStyle = col[a]; cx.lineWidth = 2; cx.beginPath(); cx.moveTo(o[0], o[1]); cx.lineTo(o[0] + sx, o[1] + sy); cx.stroke();
    cx.fillStyle = col[a]; cx.fillText(names[a], o[0] + 1.2 * sx - 3, o[1] + 1.2 * sy + 4);
  }
}
function draw(k) {
  cur = k; frIn.value = k; B = basis();
  SC = V.zoom * Math.min(cv.width, cv.height) / (1.15 * ext);
  const row = D.f[k], r = cv.getBoundingClientRect(), mag = +ellSel.value;
  const st = { frame: k * D.stride, canvas: [r.left, r.top, cv.width, cv.height], nodes: {}, bones: [], ellipses: 0,
    view: { yaw: +V.yaw.toFixed(3), pitch: +V.pitch.toFixed(3), zoom: +V.zoom.toFixed(3) }, labels: [] };
  cx.fillStyle = '#fbfbfb'; cx.fillRect(0, 0, cv.width, cv.height);
  drawGrid();
  const base = 2 * S + NM;
  // ellipsoids (under everything that moves)
  for (let k2 = 0; k2 < S; k2++) {
    const s = D.seg[k2], e = s.ell;
    if (e < 0 || row[3 * base + 6 * e] === null || mag <= 0) continue;
    const a = pt(row, k2); if (!a) continue;
    const c = row.slice(3 * base + 6 * e, 3 * base + 6 * e + 6), q = proj(a);
    // to the canonical axes: permute, the up row and column signed
    const idx = [ax0, ax1, upAx], full = [[c[0], c[3], c[4]], [c[3], c[1], c[5]], [c[4], c[5], c[2]]];
    const g = (i, j) => full[idx[i]][idx[j]] * (i === 2 ? D.sgn : 1) * (j === 2 ? D.sgn : 1);
    const el = ellipse([g(0, 0), g(1, 1), g(2, 2), g(0, 1), g(0, 2), g(1, 2)]);
    cx.fillStyle = 'rgba(214,40,40,0.22)'; cx.strokeStyle = 'rgba(170,20,20,0.9)'; cx.lineWidth = 1.2;
    cx.beginPath(); cx.ellipse(q[0], q[1], Math.max(1, mag * el[0] * SC), Math.max(1, mag * el[1] * SC), -el[2], 0, 2 * Math.PI);
    cx.fill(); cx.stroke(); st.ellipses++;
  }
  // bones
  cx.lineCap = 'round';
  for (let k2 = 0; k2 < S; k2++) {
    const s = D.seg[k2]; if (!s.in) continue;
    const a = pt(row, k2); if (!a) continue; const qa = proj(a);
    if (s.parent >= 0) {
      const b = pt(row, s.parent);
      if (b) { const qb = proj(b); cx.strokeStyle = '#333'; cx.lineWidth = 6; cx.setLineDash([]);
        cx.beginPath(); cx.moveTo(qb[0], qb[1]); cx.lineTo(qa[0], qa[1]); cx.stroke(); st.bones.push([qb[0], qb[1], qa[0], qa[1]]); }
    }
    if (s.leaf) {
      const e = pt(row, S + k2);
      if (e) { const qe = proj(e); cx.strokeStyle = '#333'; cx.lineWidth = 6; cx.setLineDash([10, 6]);
        cx.beginPath(); cx.moveTo(qa[0], qa[1]); cx.lineTo(qe[0], qe[1]); cx.stroke(); cx.setLineDash([]); st.bones.push([qa[0], qa[1], qe[0], qe[1]]); }
    }
  }
  // markers, far ones first
  const mk = [];
  for (let m = 0; m < NM; m++) { const p = pt(row, 2 * S + m); if (p) mk.push([proj(p), D.mseg[m]]); }
  mk.sort((a, b) => b[0][2] - a[0][2]);
  for (const [q, g] of mk) { cx.fillStyle = g >= 0 ? D.seg[g].colour : '#aaa'; cx.beginPath(); cx.arc(q[0], q[1], 3.5, 0, 7); cx.fill(); }
  // joint centres, then their labels where they hide nothing already drawn
  const taken = [];
  const js = [];
  for (let k2 = 0; k2 < S; k2++) {
    const s = D.seg[k2]; if (!s.in) continue; const a = pt(row, k2); if (!a) continue;
    const q = proj(a); js.push([q, s.joint]); taken.push([q[0] - 7, q[1] - 7, q[0] + 7, q[1] + 7]);
    cx.fillStyle = '#d00'; cx.beginPath(); cx.arc(q[0], q[1], 6, 0, 7); cx.fill();
    st.nodes[s.joint] = [Math.round(q[0]), Math.round(q[1])];
  }
  cx.font = 'bold 12px sans-serif';
  const hit = (b) => taken.some(t => b[0] < t[2] && b[2] > t[0] && b[1] < t[3] && b[3] > t[1]);
  for (const [q, name] of js) {
    const w = cx.measureText(name).width + 6, h = 15;
    const cand = [[10, -20], [10, 6], [-10 - w, -20], [-10 - w, 6], [-w / 2, -28], [-w / 2, 12], [18, -34], [-18 - w, 20]];
    let placed = null;
    for (const [dx, dy] of cand) { const b = [q[0] + dx, q[1] + dy, q[0] + dx + w, q[1] + dy + h]; if (!hit(b)) { placed = b; break; } }
    if (!placed) { const dx = 24, dy = -40 - 16 * st.labels.length % 80; placed = [q[0] + dx, q[1] + dy, q[0] + dx + w, q[1] + dy + h]; }
    taken.push(placed);
    cx.fillStyle = 'rgba(255,255,255,0.85)'; cx.fillRect(placed[0], placed[1], w, h);
    cx.strokeStyle = '#999'; cx.lineWidth = 1; cx.beginPath(); cx.moveTo(q[0], q[1]);
    cx.lineTo(Math.max(placed[0], Math.min(q[0], placed[2])), Math.max(placed[1], Math.min(q[1], placed[3]))); cx.stroke();
    cx.fillStyle = '#111'; cx.fillText(name, placed[0] + 3, placed[1] + 12);
    st.labels.push([name].concat(placed.map(Math.round)));
  }
  drawScale();
  const t = trialOf(k), f = k * D.stride, tr = D.trials[t];
  info.textContent = 'trial ' + (t + 1) + ' of ' + D.trials.length + ': ' + tr.name + ' \u00b7 t = ' +
    ((f - tr.start) / (D.rate || 1)).toFixed(2) + ' s \u00b7 frame ' + (f - tr.start) + ' of ' + tr.frames;
  const rc = cv.getBoundingClientRect(); // after the text above: where the canvas is now
  st.canvas = [rc.left, rc.top, cv.width, cv.height];
  document.getElementById('state').textContent = JSON.stringify(st);
  document.title = 'sfit skeleton, frame ' + f;
}
function redraw() { draw(cur); }
function stop() { if (timer) { clearInterval(timer); timer = null; } document.getElementById('play').textContent = 'play'; }
document.getElementById('play').onclick = function () {
  if (timer) { stop(); return; }
  this.textContent = 'pause';
  timer = setInterval(() => draw((cur + 1) % NF), 1000 / ((D.rate || 30) / D.stride));
};
document.getElementById('reset').onclick = () => { Object.assign(V, V0, { pan: [0, 0] }); redraw(); };
frIn.max = NF - 1;
frIn.oninput = () => { stop(); draw(+frIn.value); };
ellSel.onchange = redraw;
// orbit (drag), pan (shift-drag or right button), zoom (wheel, pinch)
const ptrs = new Map();
let pinch0 = 0, zoom0 = 1;
cv.addEventListener('contextmenu', e => e.preventDefault());
cv.addEventListener('pointerdown', e => { cv.setPointerCapture(e.pointerId); ptrs.set(e.pointerId, [e.clientX, e.clientY, e.shiftKey || e.button === 2]);
  if (ptrs.size === 2) { const [a, b] = [...ptrs.values()]; pinch0 = Math.hypot(a[0] - b[0], a[1] - b[1]); zoom0 = V.zoom; } });
cv.addEventListener('pointermove', e => {
  if (!ptrs.has(e.pointerId)) return;
  const p = ptrs.get(e.pointerId), dx = e.clientX - p[0], dy = e.clientY - p[1];
  if (ptrs.size === 2) {
    ptrs.set(e.pointerId, [e.clientX, e.clientY, p[2]]);
    const [a, b] = [...ptrs.values()], d = Math.hypot(a[0] - b[0], a[1] - b[1]);
    if (pinch0 > 0) V.zoom = Math.min(50, Math.max(0.1, zoom0 * d / pinch0));
  } else if (p[2]) { V.pan[0] += dx; V.pan[1] += dy; ptrs.set(e.pointerId, [e.clientX, e.clientY, p[2]]); }
  else { V.yaw -= dx * 0.01; V.pitch = Math.min(1.55, Math.max(-1.55, V.pitch + dy * 0.01)); ptrs.set(e.pointerId, [e.clientX, e.clientY, p[2]]); }
  redraw();
});
const up = e => { ptrs.delete(e.pointerId); pinch0 = 0; };
cv.addEventListener('pointerup', up); cv.addEventListener('pointercancel', up);
cv.addEventListener('wheel', e => { e.preventDefault(); V.zoom = Math.min(50, Math.max(0.1, V.zoom * Math.exp(-e.deltaY * 0.0015))); redraw(); }, { passive: false });
cv.addEventListener('dblclick', () => { Object.assign(V, V0, { pan: [0, 0] }); redraw(); });
document.addEventListener('keydown', e => {
  const k = { ArrowLeft: [0.1, 0], ArrowRight: [-0.1, 0], ArrowUp: [0, -0.1], ArrowDown: [0, 0.1] }[e.key];
  if (k) { V.yaw += k[0]; V.pitch = Math.min(1.55, Math.max(-1.55, V.pitch + k[1])); redraw(); }
  else if (e.key === '+' || e.key === '=') { V.zoom *= 1.2; redraw(); } else if (e.key === '-') { V.zoom /= 1.2; redraw(); }
});
// #frame=N&yaw=A&pitch=B&zoom=Z&ell=K (radians): a view to link or to test
function fromHash() {
  const h = location.hash + '&' + location.search, g = (n) => { const m = new RegExp(n + '=(-?[0-9.]+)').exec(h); return m ? +m[1] : null; };
  if (g('yaw') !== null) V.yaw = g('yaw');
  if (g('pitch') !== null) V.pitch = g('pitch');
  if (g('zoom') !== null) V.zoom = g('zoom');
  if (g('ell') !== null) ellSel.value = String(g('ell'));
  const f = g('frame');
  if (f !== null) { stop(); draw(Math.min(NF - 1, Math.floor(f / D.stride))); return true; }
  return false;
}
window.onhashchange = fromHash;
const esc = (s) => s.replace(/&/g, '&amp;').replace(/</g, '&lt;');
document.getElementById('legend').innerHTML = D.seg.map(s => '<span style="color:' + s.colour + '">&#9679; ' + esc(s.name) + '</span>').join(' &nbsp; ') +
  '<br>red: joint centres and their 95 % ellipsoids (drawn at the chosen scale); dark: bones (dashed: to an end site); grey: markers of no segment. ' +
  'Units: ' + esc(D.units) + '. Drag to orbit, shift-drag or right-drag to pan, wheel or pinch to zoom, double-click to reset.';
if (!fromHash()) draw(0);
