// "Explain this pixel": a click asks the server for the pixel's tree of rays (/explain),
// shown in the panel and marked over the image. A frame of another view or scene version
// makes it stale (dimmed); once that view rests, the same pixel is explained again.
import { api } from "./api.js";
import { on, record, state } from "./state.js";

const panel = document.getElementById("panel"), explainBox = document.getElementById("explain");
const explainNote = document.getElementById("explain-note");
const marker = document.getElementById("marker"), markerCtx = marker.getContext("2d");
// The pixel explained and the view and scene version it was explained for.
let explained = null;

// The explained pixel, marked on a canvas over the image: its outline and a ring around it,
// dark and light so that it shows on any color.
export function drawMarker() {
  markerCtx.clearRect(0, 0, marker.width, marker.height);
  if (!explained) return;
  const cx = explained.x + 0.5, cy = explained.y + 0.5;
  for (const [color, width] of [["rgba(0,0,0,0.85)", 3], ["#ffd24a", 1.5]]) {
    markerCtx.strokeStyle = color;
    markerCtx.lineWidth = width;
    markerCtx.beginPath();
    markerCtx.arc(cx, cy, 7, 0, 2 * Math.PI);
    markerCtx.stroke();
    markerCtx.strokeRect(explained.x - 1, explained.y - 1, 3, 3);
  }
}

function setExplainState(name, note) {
  record.explainState = name;
  panel.classList.toggle("stale", name === "stale" || name === "refreshing");
  explainNote.textContent = note || "";
  record.explainStates.push({ state: name, opacity: getComputedStyle(explainBox).opacity });
}

async function explain(x, y) {
  const response = await api(`/explain?x=${x}&y=${y}`);
  const tree = await response.json();
  record.lastExplain = tree;
  record.explains++;
  if (!response.ok) {
    explainBox.textContent = tree.error;
    return;
  }
  explained = { x, y, view: tree.view, scene: tree.scene_version };
  explainBox.textContent = describe(tree);
  drawMarker();
  const f = state.frame;
  const current = f && (f.view !== tree.view || f.scene !== tree.scene_version);
  setExplainState(current ? "stale" : "fresh", current ? "the view changed since: refreshing once it rests…" : "");
}

export function explainPixel({ x, y }) {
  explained = { x, y, view: -1, scene: -1 };
  drawMarker();
  setExplainState("refreshing", "explaining…");
  explain(x, y);
}

const outdated = f => explained && (f.view !== explained.view || f.scene !== explained.scene);

on("frame", f => {
  if (outdated(f) && record.explainState === "fresh")
    setExplainState("stale", "stale: the view or the scene changed; refreshing once the camera rests…");
});
on("done", d => {
  if (!d.final || !outdated(d) || record.explainState === "refreshing") return;
  if (explained.x >= d.width || explained.y >= d.height) {
    setExplainState("stale", "stale: the pixel is outside the new image; click a pixel to explain it");
    return;
  }
  setExplainState("refreshing", "refreshing for the new view…");
  explain(explained.x, explained.y);
});
on("resize", ({ width, height }) => {
  marker.width = width;
  marker.height = height;
  drawMarker();
});

const fmt = v => Array.isArray(v) ? "(" + v.map(c => c.toPrecision(4)).join(", ") + ")"
                                  : (typeof v === "number" ? v.toPrecision(4) : String(v));
function describeRay(ray, indent) {
  let s = `${indent}${ray.kind} ray, depth ${ray.depth}, weight ${fmt(ray.weight)}\n`;
  indent += "  ";
  if (!ray.hit) return s + `${indent}nothing hit: background ${fmt(ray.color)}\n`;
  const p = ray.primitive;
  s += `${indent}hits ${p.type} at ${p.source} (material ${p.material}), t ${fmt(ray.t)}, normal ${fmt(ray.normal)}, uv ${fmt(ray.uv)}\n`;
  s += `${indent}ambient ka·Oa ${fmt(ray.ambient)}, diffuse color D = kd·Od ${fmt(ray.diffuse_color)}` +
       (ray.texel ? ` blended with the texel ${fmt(ray.texel)}` : "") + "\n";
  for (const l of ray.lights) {
    s += `${indent}light ${l.light} (${l.type}): N·L ${fmt(l.n_dot_l)}`;
    if (l.unlit) s += `, ${l.unlit}` + (l.occluder ? ` by ${l.occluder.type} at ${l.occluder.source}` : "") + "\n";
    else s += `, f_att ${fmt(l.attenuation)}, diffuse D·(N·L) ${fmt(l.diffuse)}, R·V ${fmt(l.r_dot_v)}, specular ` +
              `ks·Os·(R·V)^n ${fmt(l.specular)} → f_att·I_L·(diffuse + specular) ${fmt(l.contribution)}\n`;
  }
  for (const b of ray.branches_not_traced) s += `${indent}${b.branch} branch not traced: ${b.reason}\n`;
  for (const c of ray.children)
    s += `${indent}+ ${c.factor_name} ${fmt(c.factor)} × the clamped color of:\n` + describeRay(c, indent + "  ");
  return s + `${indent}= ${fmt(ray.color)}\n`;
}
function describe(tree) {
  let s = `pixel (${tree.pixel[0]}, ${tree.pixel[1]}) of ${tree.width}x${tree.height}, depth ${tree.depth}\n`;
  for (const smp of tree.samples)
    s += `sample ${smp.index}` + (smp.time !== undefined ? `, shutter time ${fmt(smp.time)}` : "") +
         ` ${fmt(smp.color)}\n` + describeRay(smp.ray, "  ");
  return s + `color ${fmt(tree.color)}, clamped ${fmt(tree.clamped)}, 8-bit (${tree.bytes.join(", ")})\n`;
}
