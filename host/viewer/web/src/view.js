// The ray-traced view: canvas#view shows the frames the server streams (/events), tile by
// tile. It fills the space the window leaves it and follows its size (or keeps a size
// chosen in the render settings). A preview smaller than the view (the server renders
// one while something moves, when the view is slow to render: viewer/preview_resolution.h)
// is drawn into a canvas of its own size and scaled up to the view as its tiles arrive.
import { api, eventStream, latestOnly } from "./api.js";
import { emit, logFrame, record, state } from "./state.js";

const MIN_SIDE = 8, MAX_SIDE = 2048;  // viewer/view_request.h kMinViewSide, kMaxViewSide
const viewport = document.getElementById("viewport");
const canvas = document.getElementById("view"), ctx = canvas.getContext("2d");
// The canvases drawn over the view in its pixels' place: the explained pixel's marker and
// the overlay (the gizmo and the selection's outline, overlay.js).
const stacked = [canvas, document.getElementById("marker"), document.getElementById("overlay")];
const statusLine = document.getElementById("status");
const sizeChoice = document.getElementById("size");

// The preview being drawn when it is smaller than the view.
const preview = document.createElement("canvas"), previewCtx = preview.getContext("2d");
let blitPending = false;

// The views asked for, by the number the server gave each (the frames that show a view
// carry it): what is drawn over a frame is drawn in the camera of the view it shows, not in
// the latest, which the image reaches a frame or two later.
const viewsByNumber = new Map();
const postView = latestOnly(async view => {
  const response = await api("/view", { method: "POST", body: JSON.stringify(view) });
  const answer = await response.json().catch(() => ({}));
  if (response.ok && answer.view !== undefined) {
    viewsByNumber.set(answer.view, view);
    if (viewsByNumber.size > 64) viewsByNumber.delete(viewsByNumber.keys().next().value);
  }
  return answer;
});

// The view that frame `f` shows: the latest asked for at or before its number (edits count
// too, and change no camera).
export function viewOfFrame(f) {
  let best = null, bestNumber = -1;
  for (const [number, view] of viewsByNumber) if (number <= f.view && number > bestNumber) [best, bestNumber] = [view, number];
  return best || state.view;
}

// Changes the view (camera or settings, any of its fields) and asks the server for it.
export function sendView(changes) {
  Object.assign(state.view, changes);
  emit("view", state.view);
  return postView({ ...state.view });
}

// The size the view is rendered at: the viewport's in CSS pixels, or the size chosen.
function wantedSize() {
  if (sizeChoice.value !== "window") return sizeChoice.value.split("x").map(Number);
  const clamp = v => Math.max(MIN_SIDE, Math.min(MAX_SIDE, Math.round(v)));
  return [clamp(viewport.clientWidth), clamp(viewport.clientHeight)];
}

// The canvases' box on the page: the viewport's, or the chosen size's at the top left.
function placeCanvases(width, height) {
  const fits = sizeChoice.value === "window";
  for (const c of stacked) {
    c.style.width = fits ? "100%" : `${width}px`;
    c.style.height = fits ? "100%" : `${height}px`;
  }
}

let resizeTimer = null;
function followSize() {
  clearTimeout(resizeTimer);
  // A window dragged larger sends one request when it stops, not one for every step.
  resizeTimer = setTimeout(() => {
    const [width, height] = wantedSize();
    placeCanvases(width, height);
    if (state.view && (width !== state.view.width || height !== state.view.height)) sendView({ width, height });
  }, 120);
}

export function initView(view) {
  const sizeName = `${view.width}x${view.height}`;
  if (!view.fit_window) {
    if (![...sizeChoice.options].some(o => o.value === sizeName)) sizeChoice.add(new Option(sizeName));
    sizeChoice.value = sizeName;
  }
  placeCanvases(view.width, view.height);
  new ResizeObserver(followSize).observe(viewport);
  sizeChoice.addEventListener("change", followSize);
  followSize();
}

// The view's pixel under a pointer event, or null outside the image.
export function pixelAt(event) {
  const r = canvas.getBoundingClientRect();
  const x = Math.floor((event.clientX - r.left) * canvas.width / r.width);
  const y = Math.floor((event.clientY - r.top) * canvas.height / r.height);
  return x < 0 || y < 0 || x >= canvas.width || y >= canvas.height ? null : { x, y };
}

function resizeCanvas(width, height) {
  if (canvas.width === width && canvas.height === height) return;
  canvas.width = width;
  canvas.height = height;
  emit("resize", { width, height });
}

function tileImage(tile) {
  const bytes = atob(tile.rgb), image = new ImageData(tile.w, tile.h), data = image.data;
  for (let i = 0, j = 0; i < bytes.length; i += 3, j += 4) {
    data[j] = bytes.charCodeAt(i);
    data[j + 1] = bytes.charCodeAt(i + 1);
    data[j + 2] = bytes.charCodeAt(i + 2);
    data[j + 3] = 255;
  }
  return image;
}

// The preview, scaled to the view, once a frame of the browser (however many tiles came).
function blitPreview() {
  blitPending = false;
  ctx.imageSmoothingEnabled = true;
  ctx.drawImage(preview, 0, 0, canvas.width, canvas.height);
}

function drawTile(tile) {
  const image = tileImage(tile);
  if (state.frame.divisor > 1) {
    previewCtx.putImageData(image, tile.x, tile.y);
    if (!blitPending) {
      blitPending = true;
      requestAnimationFrame(blitPreview);
    }
  } else {
    ctx.putImageData(image, tile.x, tile.y);
  }
}

function onFrame(f) {
  state.frame = f;
  f.tiles = 0;
  resizeCanvas(f.view_width, f.view_height);
  if (f.divisor > 1) {
    preview.width = f.width;
    preview.height = f.height;
  }
  record.frames++;
  statusLine.textContent = `frame ${f.frame}: ` +
    (f.final ? "rendering…" : f.divisor > 1 ? `preview at 1/${f.divisor} size…` : "preview, one sample a pixel…");
  emit("frame", f);
}

function onDone(d) {
  const f = state.frame;
  record.completeFrame = d.frame;
  logFrame({ frame: d.frame, at: performance.now(), divisor: d.divisor, final: d.final, seconds: d.seconds,
             width: f.width, height: f.height, drawMs: f.drawMs || 0 });
  const what = d.final ? `AA ${d.aa}` : d.divisor > 1 ? `preview at ${f.width}x${f.height}` : "preview";
  statusLine.textContent = `${d.device} · ${canvas.width}x${canvas.height} · ${what} · ${d.rays} rays in ` +
    `${d.seconds.toFixed(3)} s · ${d.mrays.toFixed(2)} Mrays/s`;
  if (d.final) record.restFrame = { frame: d.frame, aa: d.aa, view: d.view, scene: d.scene };
  emit("done", { ...d, width: canvas.width, height: canvas.height });
}

// Listens to the server's frames and scene changes.
export function streamFrames() {
  const events = eventStream();
  events.addEventListener("frame", e => onFrame(JSON.parse(e.data)));
  events.addEventListener("tile", e => {
    const tile = JSON.parse(e.data);
    if (!state.frame || tile.frame !== state.frame.frame) return;
    const began = performance.now();
    drawTile(tile);
    state.frame.drawMs = (state.frame.drawMs || 0) + performance.now() - began;
    if (++state.frame.tiles === 1) record.firstTileAt = performance.now();
  });
  events.addEventListener("done", e => {
    const d = JSON.parse(e.data);
    if (state.frame && d.frame === state.frame.frame) onDone(d);
  });
  events.addEventListener("scene", e => emit("scene", JSON.parse(e.data)));
}

// "save image": the canvas as a PNG download.
export function saveImage() {
  const a = document.createElement("a");
  a.download = "ray-view.png";
  a.href = canvas.toDataURL("image/png");
  a.click();
}
