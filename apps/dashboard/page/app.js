// sarloc dashboard page: one event stream (/events) keeps a copy of the picture; rendering is
// batched into animation frames. No library, nothing from elsewhere.
"use strict";

const picture = { victims: new Map(), responders: new Map(), teams: new Map(), alarms: new Map(), events: [], building: null,
                  missionNs: 0, epochNs: 0, wallMs: 0, receivedAtMs: 0, parIntervalS: 600 };
// The view follows the data (fits it) until the operator pans or zooms.
const view = { x: 0, y: 0, w: 100, h: 100, userMoved: false };
let drawing = null;  // the deposit's corners while the operator draws it ([east, north], m)
const CHI2_95 = 5.991464547107979;
window.sarlocFrameTimes = [];   // render durations (ms), for the browser test
window.sarlocLatencies = [];    // server push to browser (ms)
window.sarlocSampleAgesMs = [];  // a responder's sample, from its stamp to the browser (ms)
let dirty = false;

const $ = (id) => document.getElementById(id);
const esc = (s) => String(s).replace(/[&<>"]/g, (c) => ({ "&": "&amp;", "<": "&lt;", ">": "&gt;", '"': "&quot;" })[c]);
// Mission time as T+m:ss from the mission's epoch.
const missionS = (ns) => {
  const s = Math.max(0, Math.round((ns - picture.epochNs) / 1e9));
  return `T+${Math.floor(s / 60)}:${String(s % 60).padStart(2, "0")}`;
};

// The token in the address bar (#token=...) is used once: it opens a session (an HttpOnly
// cookie the page cannot read) and leaves the address bar. The operator's token stays in the
// tab's session storage for actions; looking needs only the session.
function token() { return $("token").value.trim(); }
const tokenFromUrl = new URLSearchParams(location.hash.slice(1)).get("token");
if (tokenFromUrl) history.replaceState(null, "", location.pathname + location.search);
$("token").value = tokenFromUrl || sessionStorage.getItem("sarloc-token") || "";
if (tokenFromUrl) sessionStorage.setItem("sarloc-token", tokenFromUrl);
let connected = false;
async function signIn() {
  const session = await fetch("/api/session").then((r) => r.json()).catch(() => ({ signed_in: false }));
  if (session.signed_in) return true;
  if (!token()) return false;
  const opened = await fetch("/api/session", { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify({ token: token() }) });
  return opened.ok;
}
async function start() {
  if (connected) return;
  if (await signIn()) {
    connected = true;
    connect();
  } else {
    $("status").textContent = "sign in: enter the access token";
    $("status").className = "bad";
  }
}
$("token").addEventListener("change", () => {
  sessionStorage.setItem("sarloc-token", token());
  start();
});

const TRACK_LENGTH = 120;

function merge(message) {
  for (const kind of ["victims", "teams", "alarms"]) {
    for (const item of message[kind] || []) picture[kind].set(String(item.id), item);
  }
  // A delta's responder has no track: its new position extends the one we keep. How old each
  // sample is on arrival (its stamp is the publisher's clock: meaningful at speedup 1).
  for (const r of message.responders || []) {
    if (message.type === "delta") window.sarlocSampleAgesMs.push(Date.now() - r.stamp_ns / 1e6);
    if (!r.track) {
      const before = picture.responders.get(String(r.id));
      r.track = before ? before.track : [];
      const last = r.track[r.track.length - 1];
      if (!last || last[0] !== r.x || last[1] !== r.y) r.track.push([r.x, r.y]);
      if (r.track.length > TRACK_LENGTH) r.track.splice(0, r.track.length - TRACK_LENGTH);
    }
    picture.responders.set(String(r.id), r);
  }
  for (const r of message.removed || []) picture[r.kind === "victim" ? "victims" : "alarms"].delete(String(r.id));
  if (message.plan) picture.plan = message.plan;
  if (message.plan && message.plan.deposit && message.plan.deposit.length) picture.deposit = message.plan.deposit;
  for (const e of message.events || []) picture.events.push(e);
  if (picture.events.length > 500) picture.events.splice(0, picture.events.length - 500);
  picture.missionNs = message.mission_ns;
  picture.epochNs = message.epoch_ns;
  picture.wallMs = message.wall_ms;
  picture.receivedAtMs = Date.now();
  if (message.wall_ms) window.sarlocLatencies.push(Date.now() - message.wall_ms);
  if (window.sarlocLatencies.length > 10000) window.sarlocLatencies.splice(0, 5000);
  schedule();
}

// A replay's timeline (sarloc-dashboard --recording): shown when the server says so.
let scrubbing = false;
let replayPlaying = false;
let replaying = false;
function showReplay(replay) {
  if (!replay) return;
  $("replay").hidden = false;
  replaying = true;  // a replay changes nothing: no drawing, no editing
  $('draw').hidden = $('edit').hidden = true;
  replayPlaying = replay.playing;
  $("play").textContent = replay.playing ? "pause" : "play";
  $("scrub").min = replay.start_s;
  $("scrub").max = replay.end_s;
  if (!scrubbing) $("scrub").value = replay.cursor_s;
  $("replay-time").textContent = `${replay.cursor_s.toFixed(0)} s of ${replay.end_s.toFixed(0)} s`;
}
async function replayControl(request) {
  const response = await fetch("/api/replay", { method: "POST", headers: { "Content-Type": "application/json" }, body: JSON.stringify(request) });
  if (response.ok) showReplay(await response.json());
}
$("play").addEventListener("click", () => replayControl(replayPlaying ? { action: "pause" } : { action: "play", rate: Number($("rate").value) }));
$("scrub").addEventListener("input", () => { scrubbing = true; });
$("scrub").addEventListener("change", async () => { await replayControl({ action: "seek", t_s: Number($("scrub").value) }); scrubbing = false; });
window.sarlocReplay = replayControl;

function connect() {
  const source = new EventSource("/events");
  source.addEventListener("snapshot", (e) => {
    const s = JSON.parse(e.data);
    for (const kind of ["victims", "responders", "teams", "alarms"]) picture[kind].clear();
    picture.events = [];
    picture.building = s.building && s.building.floors ? s.building : null;
    picture.deposit = Array.isArray(s.deposit) ? s.deposit : [];
    picture.basemap = Array.isArray(s.basemap) ? s.basemap : [];
    picture.plan = s.plan || null;
    picture.parIntervalS = s.par_interval_s;
    fillFloors();
    merge(s);
    showReplay(s.replay);
    showTrust(s.dds_security);
    if (s.incident) $("incident").textContent = s.incident.name || s.incident.id;
  });
  source.addEventListener("delta", (e) => merge(JSON.parse(e.data)));
  source.addEventListener("heartbeat", (e) => {
    const h = JSON.parse(e.data);
    picture.missionNs = h.mission_ns;
    showReplay(h.replay);
    showTrust(h.dds_security);
    $("banner").hidden = !h.stale;
    $('banner-age').textContent = h.data_age_s < 0 ? 'ever (since it started)' : `${h.data_age_s.toFixed(0)} s`;
    schedule();
  });
  source.onopen = () => { $("status").textContent = "live"; $("status").className = "ok"; };
  source.onerror = () => { $("status").textContent = "reconnecting…"; $("status").className = "bad"; };
}

// Whether what this page shows could have been written by anyone on the network: in red
// unless the dashboard's participant runs DDS Security (authenticated and encrypted).
function showTrust(security) {
  if (security === undefined) return;
  const secured = security === "authenticated, encrypted";
  $("dds").textContent = secured ? "DDS authenticated, encrypted"
    : security === "recording" ? "DDS: a recording" : "DDS NOT AUTHENTICATED: anyone on the network can change this picture";
  $("dds").className = secured || security === "recording" ? "ok" : "alarm";
}

function fillFloors() {
  const select = $("floor");
  const floors = picture.building ? picture.building.floors : [{ id: "ground" }];
  select.innerHTML = floors.map((f, i) => `<option value="${i}">${i} (${esc(f.id)})</option>`).join("");
}

function schedule() {
  if (!dirty) { dirty = true; requestAnimationFrame(render); }
}

// A 95 % ellipse, drawn at least `minimum` across so that it stays visible at any zoom (its
// radius is in the label).
function ellipse(x, y, cov, cls, minimum = 0) {
  const [a, b, c] = cov;
  const mean = (a + c) / 2, diff = Math.sqrt(((a - c) / 2) ** 2 + b * b);
  const l1 = Math.max(mean + diff, 1e-6), l2 = Math.max(mean - diff, 1e-6);
  const angle = (0.5 * Math.atan2(2 * b, a - c) * 180) / Math.PI;
  const rx = Math.max(Math.sqrt(CHI2_95 * l1), minimum), ry = Math.max(Math.sqrt(CHI2_95 * l2), minimum);
  return `<ellipse class="${cls}" cx="${x}" cy="${-y}" rx="${rx}" ry="${ry}" transform="rotate(${-angle} ${x} ${-y})"/>`;
}

// Labels placed where they overlap no label placed before: the first free one of eight spots
// around the point, then further out. Sizes in map units (px = map units per screen pixel).
// The box is the text's as drawn (12 px sans-serif, up to 7.5 px a character, 17 px high with
// its descenders), so that two boxes apart are two labels apart (the e2e test measures them).
function labeller(px) {
  const placed = [];
  return (x, y, text) => {
    const w = (7.5 * text.length + 6) * px, h = 17 * px;
    const near = [[7, -7], [7, 17], [-7 - w / px, -7], [-7 - w / px, 17], [-w / px / 2, -14], [-w / px / 2, 30]];
    // Then rings further out, one label height at a time: a crowd's labels stack beside it.
    const spots = [...near];
    for (let ring = 1; ring <= 8; ++ring) for (const side of [1, -1]) spots.push([7, -7 + side * ring * 18], [-7 - w / px, -7 + side * ring * 18]);
    let box = null;
    for (const [dx, dy] of spots) {
      const candidate = { x: x + dx * px, y: -y + dy * px, w, h };
      if (!placed.some((b) => candidate.x < b.x + b.w && b.x < candidate.x + candidate.w && candidate.y - candidate.h < b.y && b.y - b.h < candidate.y)) {
        box = candidate;
        break;
      }
    }
    box = box || { x: x + 7 * px, y: -y - 7 * px - (placed.length % 8) * 18 * px, w, h };
    placed.push(box);
    return `<text x="${box.x}" y="${box.y}" font-size="${12 * px}" stroke-width="${3 * px}">${esc(text)}</text>`;
  };
}

// The areas a commander looks at: where people and victims are now, split where they are far
// apart (an avalanche field and a building 80 m away are two areas, not one box around both).
const AREA_GAP_M = 40;
function areas() {
  const points = [];
  const add = (x, y) => { if (isFinite(x) && isFinite(y)) points.push([x, y]); };
  picture.victims.forEach((v) => add(v.x, v.y));
  picture.responders.forEach((r) => add(r.x, r.y));
  if (picture.building && !points.length) for (const w of picture.building.floors[0].walls) { add(w[0], w[1]); add(w[2], w[3]); }
  if (!points.length)
    for (const p of picture.deposit || []) add(p[0], p[1]);
  // Single linkage: a point within AREA_GAP_M of an area joins it.
  const groups = [];
  for (const p of points) {
    const near = groups.filter((g) => g.some((q) => Math.hypot(p[0] - q[0], p[1] - q[1]) < AREA_GAP_M));
    const merged = [p, ...near.flat()];
    for (const g of near) groups.splice(groups.indexOf(g), 1);
    groups.push(merged);
  }
  return groups.sort((a, b) => b.length - a.length);
}
let areaChoice = "all";
function fit() {
  const groups = areas();
  const chosen = areaChoice === "all" ? groups.flat() : groups[Number(areaChoice)] || groups.flat();
  if (!chosen.length) return;
  const buttons = ["all", ...groups.map((_, i) => String(i))];
  if ($("area").options.length !== buttons.length) {
    $("area").innerHTML = buttons.map((b) => `<option value="${b}">${b === "all" ? "everything" : `area ${Number(b) + 1} (${groups[Number(b)].length})`}</option>`).join("");
    $("area").value = buttons.includes(areaChoice) ? areaChoice : "all";
  }
  frame(chosen);
}

// The view around `points` ([east, north]) with 10 m around them.
function frame(points) {
  const xs = points.map((p) => p[0]), ys = points.map((p) => p[1]);
  const minX = Math.min(...xs) - 10, maxX = Math.max(...xs) + 10, minY = Math.min(...ys) - 10,
        maxY = Math.max(...ys) + 10;
  const box = $("map").getBoundingClientRect();
  const aspect = box.width > 0 && box.height > 0 ? box.width / box.height : 1.5;
  let w = maxX - minX, h = maxY - minY;
  if (w / h < aspect) w = h * aspect; else h = w / aspect;
  Object.assign(view, {x: (minX + maxX) / 2 - w / 2, y: -(minY + maxY) / 2 - h / 2, w, h});
}

const COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf", "#8c564b", "#e377c2"];

function renderMap() {
  if (!view.userMoved) fit();
  const floor = Number($("floor").value || 0);
  const px = view.w / Math.max(1, $("map").getBoundingClientRect().width);  // metres per pixel
  let svg = "";
  const label = labeller(px);
  // The offline basemap (dashboard.basemap) under everything: terrain around the deposit. Each
  // tile a hair larger than its place, so no seam shows between neighbours.
  for (const t of picture.basemap || []) {
    svg += `<image class="basemap" href="/api/basemap/${t.z}/${t.x}/${t.y}" x="${t.west}" y="${- t.north}" width="${
        t.width + 0.5 * px}" height="${t.height + 0.5 * px}" preserveAspectRatio="none"/>`;
  }
  // The avalanche deposit over the basemap: where the primary search must go.
  if (picture.deposit && picture.deposit.length >= 3) {
    const points = picture.deposit.map((p) => `${p[0]},${- p[1]}`).join(' ');
    svg += `<polygon points="${points}" fill="#cfe3f7" fill-opacity="0.45" stroke="#5b8db8" stroke-width="${
        1.5 * px}" stroke-dasharray="${6 * px},${4 * px}"/>`;
  }
  // Incident command's search plan over it: each strip shaded by what is searched, its rescuer
  // (and a helper walking up from the bottom) and share at its top, and a ring where each walks next.
  const planLabels = [];
  for (const strip of (picture.plan && picture.plan.strips) || []) {
    if (!Array.isArray(strip.outline) || strip.outline.length < 3) continue;
    const points = strip.outline.map((p) => `${p[0]},${- p[1]}`).join(' ');
    svg += `<polygon class="strip" points="${points}" fill="#2e8b57" fill-opacity="${
        (0.05 + 0.3 * strip.searched).toFixed(3)}" stroke="#5b8db8" stroke-width="${px}"/>`;
    for (const next of [strip.next, strip.helper_next]) {
      if (!Array.isArray(next)) continue;
      svg += `<circle cx="${next[0]}" cy="${- next[1]}" r="${4 * px}" fill="none" stroke="#2e8b57" stroke-width="${
          1.5 * px}"/>`;
    }
    const walker = strip.rescuer ? strip.rescuer : strip.done ? 'done' : 'open';
    const who = strip.helper ? `${walker}, helped by ${strip.helper}` : walker;
    planLabels.push(
        [strip.top[0], strip.top[1], `strip ${strip.index}: ${who}, ${Math.round(100 * strip.searched)} %`]);
  }
  if (picture.building && picture.building.floors[floor]) {
    for (const w of picture.building.floors[floor].walls) {
      svg += `<line x1="${w[0]}" y1="${-w[1]}" x2="${w[2]}" y2="${-w[3]}" stroke="#333" stroke-width="${3 * px}"/>`;
    }
    for (const d of picture.building.floors[floor].doors) {
      svg += `<circle cx="${d.x}" cy="${-d.y}" r="${d.width_m / 2}" fill="#8fbc8f" fill-opacity="0.5"/>`;
    }
  }
  const labels = [];
  let k = 0;
  for (const r of picture.responders.values()) {
    const colour = COLOURS[k++ % COLOURS.length];
    const indoors = r.source === "map-aided" || r.source === "dead reckoning";
    const candidates = r.candidates || [];
    // Ambiguous: each place it may be in, with its share; the mean between them is no place.
    if (candidates.length) {
      for (const c of candidates) {
        if (c.floor !== floor) continue;
        svg += ellipse(c.x, c.y, c.cov, '', 6 * px)
                   .replace(
                       '<ellipse',
                       `<ellipse data-candidate="${esc(r.id)}" fill="${colour}" fill-opacity="0.08" stroke="${
                           colour}" stroke-width="${1.5 * px}" stroke-dasharray="${4 * px},${3 * px}"`);
        svg +=
            `<circle cx="${c.x}" cy="${- c.y}" r="${4 * px}" fill="#fff" stroke="${colour}" stroke-width="${2 * px}"/>`;
        labels.push([c.x, c.y, `${r.id}? ${Math.round(100 * c.weight)} %`]);
      }
      continue;
    }
    if (indoors && r.floor !== floor) continue;
    if (r.track.length > 1) {
      svg += `<polyline fill="none" stroke="${colour}" stroke-width="${2 * px}" stroke-opacity="0.7" points="${r.track.map((p) => `${p[0]},${-p[1]}`).join(" ")}"/>`;
    }
    // A map-aided estimate not yet converged is a mean over a spread cloud: drawn hollow and dashed.
    const placed = r.source !== 'map-aided' || r.converged;
    if (indoors) {
      svg += ellipse(r.x, r.y, r.cov, '', 4 * px)
                 .replace(
                     '<ellipse',
                     `<ellipse fill="none" stroke="${colour}" stroke-width="${px}"${
                         placed ? '' : ` stroke-dasharray="${4 * px},${3 * px}"`}`);
    }
    svg += `<circle data-responder="${esc(r.id)}" cx="${r.x}" cy="${- r.y}" r="${5 * px}" fill="${
        placed ? colour : '#fff'}" stroke="${placed ? '#fff' : colour}" stroke-width="${placed ? px : 2 * px}"/>`;
    if (r.heading_rad !== null && !indoors) {
      const L = 30 * px, hx = r.x + L * Math.cos(r.heading_rad), hy = r.y + L * Math.sin(r.heading_rad);
      svg += `<line x1="${r.x}" y1="${-r.y}" x2="${hx}" y2="${-hy}" stroke="${colour}" stroke-width="${2.5 * px}" marker-end="url(#arrow)"/>`;
    }
    labels.push([r.x, r.y, placed ? r.id : `${r.id} (not yet placed)`]);
  }
  for (const v of picture.victims.values()) {
    const colour = v.state === 'FOUND' ? '#1b7f1b' :
        v.state === 'recovered'        ? '#1f5fa8' :
        v.state === 'LOCATED'          ? '#c96a00' :
                                         '#777';
    svg += ellipse(v.x, v.y, v.cov, "", 4 * px).replace("<ellipse", `<ellipse data-victim="${v.id}" fill="${colour}" fill-opacity="0.18" stroke="${colour}" stroke-width="${2 * px}"`);
    svg += `<path d="M${v.x - 5 * px} ${-v.y - 5 * px} L${v.x + 5 * px} ${-v.y + 5 * px} M${v.x - 5 * px} ${-v.y + 5 * px} L${v.x + 5 * px} ${-v.y - 5 * px}" stroke="${colour}" stroke-width="${2.5 * px}"/>`;
    labels.push([
      v.x, v.y, v.state === 'recovered' ? `victim ${v.id} dug out` : `victim ${v.id} ±${v.radius95_m.toFixed(1)} m`
    ]);
  }
  for (const a of picture.alarms.values()) {
    if (!a.position_known || !a.active) continue;
    svg += `<circle cx="${a.x}" cy="${-a.y}" r="${12 * px}" fill="none" stroke="#b00020" stroke-width="${3 * px}"/>`;
  }
  // Victims' labels first: they matter most where labels crowd.
  labels.sort((a, b) => String(b[2]).startsWith("victim") - String(a[2]).startsWith("victim"));
  for (const [x, y, text] of [...labels, ...planLabels]) svg += label(x, y, text);
  // Scale bar: a round length near a fifth of the view.
  const target = view.w / 5, base = 10 ** Math.floor(Math.log10(target));
  const bar = [5, 2, 1].map((f) => f * base).find((b) => b <= target);
  const bx = view.x + 10 * px, by = view.y + view.h - 12 * px;
  svg += `<line x1="${bx}" y1="${by}" x2="${bx + bar}" y2="${by}" stroke="#111" stroke-width="${3 * px}"/>`;
  svg += `<text x="${bx}" y="${by - 5 * px}" font-size="${11 * px}" stroke-width="${3 * px}">${bar} m</text>`;
  // The outline the operator is drawing, over everything else.
  if (drawing && drawing.length) {
    const points = drawing.map((p) => `${p[0]},${- p[1]}`).join(' ');
    svg += `<polyline points="${points}${
        drawing.length > 2 ?
            ` ${drawing[0][0]},${- drawing[0][1]}` :
            ''}" fill="none" stroke="#d35400" stroke-width="${2 * px}" stroke-dasharray="${5 * px},${3 * px}"/>`;
    for (const p of drawing)
      svg += `<circle class="drawn-corner" cx="${p[0]}" cy="${- p[1]}" r="${4 * px}" fill="#d35400"/>`;
  }
  const defs = `<defs><marker id="arrow" viewBox="0 0 10 10" refX="5" refY="5" markerWidth="4" markerHeight="4" orient="auto-start-reverse"><path d="M0 0 L10 5 L0 10 z" fill="#333"/></marker></defs>`;
  $("map").setAttribute("viewBox", `${view.x} ${view.y} ${view.w} ${view.h}`);
  $("map").innerHTML = defs + svg;
  $('edit').hidden = replaying || drawing !== null || !(picture.deposit && picture.deposit.length >= 3);
}

const isFound = (state) => state === 'FOUND' || state === 'recovered';

// "r1/1", "r2/1" -> "r1, r2": who heard the victim (the signal numbers are in the tooltip).
const heardBy = (sources) => [...new Set(sources.map((s) => s.split("/")[0]))].join(", ") || "—";

// The one rescuer incident command sends to a victim heard by several (the search plan).
const pursuer = (victimId) => (picture.plan && picture.plan.pursuers && picture.plan.pursuers[victimId]) || '';

// A list's HTML is replaced only when it changed, and what changes every second (ages, the PAR
// countdown) is written into its cells afterwards: a row replaced between the press and the
// release of a button under the operator's pointer loses the click (seen in the browser test,
// once a second with the ages inside the rows).
function setRows(element, html) {
  if (element.sarlocHtml === html) return;
  element.innerHTML = html;
  element.sarlocHtml = html;
}

function fillClocks(now, wallNow) {
  for (const cell of document.querySelectorAll('[data-since-ns]')) {
    cell.textContent = `${((now - Number(cell.dataset.sinceNs)) / 1e9).toFixed(0)} s ago`;
  }
  for (const span of document.querySelectorAll('.par[data-due-ms]')) {
    const left = (Number(span.dataset.dueMs) - wallNow) / 1000;
    span.className = `par ${left < 0 ? 'red' : left < 60 ? 'amber' : ''}`;
    span.textContent = left < 0 ? `PAR overdue ${(-left).toFixed(0)} s` :
                                  `PAR in ${Math.floor(left / 60)}:${String(Math.floor(left % 60)).padStart(2, '0')}`;
  }
}

// How sure the member's position is, in words: what a commander may act on.
function positionCell(id) {
  const r = picture.responders.get(String(id));
  if (!r) return '<td>—</td>';
  let text = r.source, cls = '';
  if (r.source === 'map-aided') {
    const places = r.candidates || [];
    if (r.confirmed)
      [text, cls] = ['confirmed', 'placed'];
    else if (r.converged)
      [text, cls] = ['converged', 'placed'];
    else if (r.ambiguous && places.length)
      [text, cls] = [
        `one of ${places.length} places: ${places.map((c) => `${Math.round(100 * c.weight)} %`).join(', ')}`,
        'ambiguous'
      ];
    else
      [text, cls] = ['not yet placed', 'unplaced'];
    if (r.map_error) [text, cls] = [`${text}; map error suspected`, 'ambiguous'];
  }
  return `<td class="position ${cls}">${esc(text)}</td>`;
}

function renderLists() {
  const now = picture.missionNs;
  const victims = [...picture.victims.values()].sort((a, b) => a.id - b.id);
  $("victim-count").textContent = victims.length;
  setRows(
      $('victims').tBodies[0],
      victims
          .map(
              (v) =>
                  `<tr data-victim="${v.id}"><td>${v.id}${v.conflict ? ' <b class="error">conflict</b>' : ''}</td>` +
                  `<td class="state state-${esc(v.state)}">${esc(v.state)}</td><td>${v.radius95_m.toFixed(2)}</td>` +
                  `<td class="where">${v.x.toFixed(1)} E, ${v.y.toFixed(1)} N${
                      v.wgs84 ? `<br><small>${esc(v.wgs84)}</small>` : ''}</td>` +
                  (v.located_ns ? `<td data-since-ns="${v.located_ns}"></td>` : '<td>—</td>') +
                  `<td class="found">${isFound(v.state) && v.found_ns ? `at ${missionS(v.found_ns)}` : '—'}${
                      v.state === 'recovered' ? ', dug out' : ''}${
                      v.state === 'FOUND' ?
                          ` <button type="button" class="dug-out" data-victim="${v.id}">dug out</button>` :
                          ''}</td>` +
                  `<td title="${esc(v.sources.join(', '))}">${esc(heardBy(v.sources))}${
                      pursuer(v.id) ? `<br><small class="pursuer">sent: ${esc(pursuer(v.id))}</small>` : ''}</td></tr>`)
          .join(''));

  // One rescuer per signal before anyone has placed it: not yet a victim, so not in the table.
  const unplaced = (picture.plan && picture.plan.unplaced_pursuits) || [];
  $('unplaced-pursuits').textContent = unplaced.length ? 'Signals not yet placed: ' +
          unplaced.map((u) => `${u.pursuer} pursues one also heard by ${u.others.join(', ')}`).join('; ') :
                                                         '';

  // Triage: incident command's dig order over the FOUND victims (survival at each dig-out).
  const digs = (picture.plan && picture.plan.digs) || [];
  $('dig-survivors').textContent = digs.length ? picture.plan.expected_survivors.toFixed(2) : '—';
  setRows(
      $('digs').tBodies[0],
      digs.map(
              (d, i) =>
                  `<tr data-dig="${d.victim}"><td>${i + 1}</td><td>${d.victim}</td><td>${d.depth_m.toFixed(1)}</td>` +
                  `<td>${d.done_min.toFixed(0)} min${
                      d.start_min > 0 ? ` <small>(starts in ${d.start_min.toFixed(0)})</small>` : ''}</td>` +
                  `<td>${Math.round(100 * d.survival)} %</td><td>${
                      d.digger ? esc(d.digger) : '<i>none free</i>'}</td>` +
                  `<td>${
                      i > 0 ? `<button type="button" class="dig-first" data-victim="${d.victim}">dig first</button>` :
                              ''}</td></tr>`)
          .join(''));

  const wallNow = picture.wallMs + (Date.now() - picture.receivedAtMs);
  setRows(
      $('teams'),
      [...picture.teams.values()]
          .sort((a, b) => a.id.localeCompare(b.id))
          .map((t) => {
            const head =
                '<tr><th>member</th><th>link</th><th>accounted</th><th>last heard</th><th>floor</th><th>position</th></tr>';
            const rows = head +
                t.members
                    .map(
                        (m) => `<tr data-member="${esc(m.id)}"><td>${esc(m.id)}</td><td class="link link-${
                                   esc(m.link)}">${esc(m.link === 'signed_off' ? 'signed off' : m.link)}</td>` +
                            `<td>${esc(m.accountability)}</td>${
                                   m.last_seen_ns ?
                                       `<td data-since-ns="${m.last_seen_ns}"></td>` :
                                       '<td>never</td>'}<td>floor ${m.floor}</td>${positionCell(m.id)}</tr>`)
                    .join('');
            return `<div class="team" data-team="${esc(t.id)}"><h3>${
                       esc(t.id || '(no team)')} <span><span class="par" data-due-ms="${t.par_due_wall_ms}"></span> ` +
                `<button type="button" class="par-report" data-team="${
                       esc(t.id)}">PAR reported</button></span></h3><table>${rows}</table></div>`;
          })
          .join(''));

  const alarms = [...picture.alarms.values()].sort((a, b) => b.raised_ns - a.raised_ns);
  $("alarm-count").textContent = alarms.filter((a) => !a.acknowledged).length;
  setRows(
      $('alarms'),
      alarms
          .map(
              (a) => `<li data-alarm="${a.id}" class="${a.active ? '' : 'cleared'} ${
                         a.acknowledged ?
                             'acknowledged' :
                             ''}"><span><b>${esc(a.name || a.kind)}</b> ${esc(a.responder)} (${esc(a.team)}), ` +
                  `raised at ${missionS(a.raised_ns)}${a.active ? '' : ', cleared'}${
                         a.acknowledged ? `, acknowledged by ${esc(a.acknowledged_by)}` : ''}</span>` +
                  (a.acknowledged ? '' :
                                    `<button type="button" class="ack" data-alarm="${a.id}">acknowledge</button>`) +
                  '</li>')
          .join(''));

  setRows(
      $('events'),
      picture.events.slice(-200)
          .reverse()
          .map((e) => `<li><b>${missionS(e.mission_ns)}</b> ${esc(e.kind)}: ${esc(e.text)}</li>`)
          .join(''));
  fillClocks(now, wallNow);
  $("clock").textContent = `mission ${missionS(now)}`;
  $("wall").textContent = new Date(picture.wallMs + (Date.now() - picture.receivedAtMs)).toLocaleTimeString([], { hour12: false });
}

function render() {
  dirty = false;
  const start = performance.now();
  renderMap();
  renderLists();
  window.sarlocFrameTimes.push(performance.now() - start);
  if (window.sarlocFrameTimes.length > 10000) window.sarlocFrameTimes.splice(0, 5000);
}

async function act(url, what, body) {
  const headers = {Authorization: `Bearer ${token()}`};
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  const response =
      await fetch(url, {method: 'POST', headers, body: body === undefined ? undefined : JSON.stringify(body)});
  if (!response.ok) {
    const body = await response.json().catch(() => ({ error: response.statusText }));
    picture.events.push({ mission_ns: picture.missionNs, kind: "dashboard", text: `${what} refused: ${body.error}` });
    schedule();
  }
  return response.status;
}
window.sarlocAct = act;

document.addEventListener("click", (e) => {
  const ack = e.target.closest("button.ack");
  if (ack) act(`/api/alarms/${ack.dataset.alarm}/ack`, `acknowledging alarm ${ack.dataset.alarm}`);
  const first = e.target.closest('button.dig-first');
  if (first) act(`/api/victims/${first.dataset.victim}/dig-first`, `digging victim ${first.dataset.victim} first`);
  const dug = e.target.closest('button.dug-out');
  if (dug) act(`/api/victims/${dug.dataset.victim}/dug-out`, `victim ${dug.dataset.victim} dug out`);
  const par = e.target.closest("button.par-report");
  if (par) act(`/api/teams/${encodeURIComponent(par.dataset.team)}/par`, `PAR of ${par.dataset.team}`);
});
$("floor").addEventListener("change", schedule);
$("fit").addEventListener("click", () => { view.userMoved = false; schedule(); });
$("area").addEventListener("change", () => { areaChoice = $("area").value; view.userMoved = false; schedule(); });

// Drawing the deposit: a press and release on the map (not a drag) adds a corner, in the incident frame
// (east, north: the map's y is south); a corner pressed and dragged moves (editing starts from the
// deposit incident command plans over). Sent whole; kept on screen if refused, to fix or cancel.
let pressedAt = null;
let movingCorner = null;  // index into drawing while the operator drags a corner
function drawMode(on, corners = []) {
  drawing = on ? corners.map((p) => [p[0], p[1]]) : null;
  if (on && corners.length) {
    frame(corners);  // every corner in view, and held there while editing
    view.userMoved = true;
  }
  $('draw').hidden = on || replaying;
  $('draw-send').hidden = $('draw-cancel').hidden = !on;
  $('hint').textContent = !on ? 'drag to pan, wheel to zoom' :
      corners.length ? 'drag a corner to move it; click to add one after the last; Backspace removes the last' :
                       'click the deposit\'s corners in order; Backspace removes the last';
  schedule();
}
// The drawn corner under the pointer (within 8 px), or -1.
function cornerAt(e) {
  if (!drawing) return -1;
  const p = mapPoint(e);
  const reach = 8 * view.w / $('map').getBoundingClientRect().width;
  return drawing.findIndex((c) => Math.hypot(c[0] - p[0], c[1] - p[1]) <= reach);
}
function mapPoint(e) {
  const box = $('map').getBoundingClientRect();
  const scale = view.w / box.width;
  return [view.x + (e.clientX - box.left) * scale, -(view.y + (e.clientY - box.top) * scale)];
}
$('draw').addEventListener('click', () => drawMode(true));
$('edit').addEventListener('click', () => drawMode(true, picture.deposit || []));
$('draw-cancel').addEventListener('click', () => drawMode(false));
$('draw-send').addEventListener('click', async () => {
  if (!drawing || drawing.length < 3) {
    picture.events.push({mission_ns: picture.missionNs, kind: 'dashboard', text: 'a deposit needs 3 corners or more'});
    return schedule();
  }
  const outline = drawing.map((p) => p.map((v) => Math.round(v * 10) / 10));  // 0.1 m
  if ((await act('/api/deposit', `the deposit of ${outline.length} corners`, {outline})) === 202) drawMode(false);
});
window.addEventListener('keydown', (e) => {
  if (!drawing || e.target.tagName === 'INPUT') return;
  if (e.key === 'Escape') drawMode(false);
  if (e.key === 'Backspace') {
    drawing.pop();
    schedule();
  }
});

// Pan and zoom on the map.
let drag = null;
$('map').addEventListener('mousedown', (e) => {
  pressedAt = {x: e.clientX, y: e.clientY};
  const corner = cornerAt(e);
  if (corner >= 0) {
    movingCorner = corner;  // moves that corner, pans nothing, adds none
    return;
  }
  drag = {x: e.clientX, y: e.clientY, vx: view.x, vy: view.y};
});
window.addEventListener('mouseup', (e) => {
  drag = null;
  if (movingCorner !== null) {
    movingCorner = null;
    pressedAt = null;
    return;
  }
  // A corner on the button's release, not on "click": the map is redrawn whole when data
  // arrives, and a click whose press landed on an element redrawn before the release is never
  // fired (seen: one corner of four lost on a loaded machine).
  if (drawing && pressedAt && Math.hypot(e.clientX - pressedAt.x, e.clientY - pressedAt.y) <= 4) {
    drawing.push(mapPoint(e));
    schedule();
  }
  pressedAt = null;
});
window.addEventListener('mousemove', (e) => {
  if (movingCorner !== null && drawing) {
    drawing[movingCorner] = mapPoint(e);
    schedule();
    return;
  }
  if (!drag) return;
  const scale = view.w / $("map").getBoundingClientRect().width;
  view.x = drag.vx - (e.clientX - drag.x) * scale;
  view.y = drag.vy - (e.clientY - drag.y) * scale;
  view.userMoved = true;
  schedule();
});
$("map").addEventListener("wheel", (e) => {
  e.preventDefault();
  const box = $("map").getBoundingClientRect();
  const fx = (e.clientX - box.left) / box.width, fy = (e.clientY - box.top) / box.height;
  const factor = e.deltaY > 0 ? 1.2 : 1 / 1.2;
  const w = view.w * factor, h = view.h * factor;
  view.x += (view.w - w) * fx;
  view.y += (view.h - h) * fy;
  view.w = w;
  view.h = h;
  view.userMoved = true;
  schedule();
}, { passive: false });
setInterval(schedule, 1000);  // timers (PAR, "s ago") move even without data
start();
