// The pointer and the keyboard over the view. A drag orbits (shift: pans), the wheel zooms,
// a click selects the object under it and explains the pixel; a press on the gizmo's
// handles is the gizmo's (overlay.js). Blender's keys: G, R, S move, rotate and scale the
// selection with the pointer (X, Y, Z constrain to an axis; a click or Enter confirms,
// Escape or a right click cancels), X or Delete deletes, Shift+D duplicates, Ctrl+Z and
// Ctrl+Shift+Z undo and redo, F frames the selection, Home resets the view.
import { Matrix4, Vector3 } from "three";
import { orbit, pan, resetView, zoom } from "./camera.js";
import { explainPixel } from "./explain.js";
import { cameraAxes, gizmoHasPointer, matrixFromRows, projectToView, unprojectToPlane } from "./overlay.js";
import { state } from "./state.js";
import { pixelAt } from "./view.js";

const overlay = document.getElementById("overlay");
const hint = document.getElementById("modal-hint");
const AXES = { x: new Vector3(1, 0, 0), y: new Vector3(0, 1, 0), z: new Vector3(0, 0, 1) };
let pointer = null;  // the pointer's last place over the view, in the view's pixels
let drag = null;     // an orbit or pan in progress
let modal = null;    // a G, R or S transform in progress

// ---- G, R, S: the world-space change the pointer makes, from where the transform began.
function modalDelta() {
  const { kind, axis, start, world, center } = modal;
  const c = new Vector3(...center), toCenter = new Matrix4().makeTranslation(c.x, c.y, c.z);
  const fromCenter = new Matrix4().makeTranslation(-c.x, -c.y, -c.z);
  if (kind === "move") {
    const a = new Vector3(...unprojectToPlane(start.x, start.y, center));
    const t = new Vector3(...unprojectToPlane(pointer.x, pointer.y, center)).sub(a);
    if (axis) t.copy(AXES[axis]).multiplyScalar(t.dot(AXES[axis]));
    return new Matrix4().makeTranslation(t.x, t.y, t.z);
  }
  const p = projectToView(center);
  if (kind === "rotate") {
    // The angle swept about the object's centre on the screen (y down: clockwise).
    const angle = Math.atan2(pointer.y - p.y, pointer.x - p.x) - Math.atan2(start.y - p.y, start.x - p.x);
    const forward = cameraAxes().forward;
    let about = forward, turn = angle;
    if (axis) {
      about = AXES[axis];
      turn = about.dot(forward) < 0 ? -angle : angle;
    }
    return toCenter.multiply(new Matrix4().makeRotationAxis(about, turn)).multiply(fromCenter);
  }
  // scale: by the ratio of the pointer's distances from the centre, along the object's own
  // axis when constrained.
  const factor = Math.hypot(pointer.x - p.x, pointer.y - p.y) / Math.max(1, Math.hypot(start.x - p.x, start.y - p.y));
  const f = Math.max(factor, 1e-3);
  const s = axis ? [axis === "x" ? f : 1, axis === "y" ? f : 1, axis === "z" ? f : 1] : [f, f, f];
  return world.clone().multiply(new Matrix4().makeScale(...s)).multiply(world.clone().invert());
}

function showHint() {
  hint.textContent = modal ? `${modal.kind}${modal.axis ? " along " + modal.axis.toUpperCase() : ""} · ` +
    "click or Enter: confirm · Escape or right click: cancel · X Y Z: axis" : "";
}

function startModal(kind, editing) {
  const sel = state.selection;
  if (modal || !sel || sel.worlds === undefined || !state.editable || !pointer) return;
  if (!editing.gesture.begin()) return;
  const world = matrixFromRows(sel.worlds[0]), e = world.elements;
  modal = { kind, axis: null, start: { ...pointer }, world, center: [e[12], e[13], e[14]] };
  showHint();
}

function endModal(editing, confirm) {
  if (!modal) return;
  const delta = modalDelta();
  modal = null;
  showHint();
  if (confirm) editing.gesture.end(delta);
  else editing.gesture.cancel();
}

function onKey(event, editing) {
  const target = event.target;
  if (target instanceof HTMLInputElement || target instanceof HTMLSelectElement || target instanceof HTMLTextAreaElement)
    return;
  const key = event.key.toLowerCase(), ctrl = event.ctrlKey || event.metaKey;
  if (modal) {
    if (key === "escape") endModal(editing, false);
    else if (key === "enter") endModal(editing, true);
    else if (key === "x" || key === "y" || key === "z") {
      modal.axis = modal.axis === key ? null : key;
      showHint();
      editing.gesture.move(modalDelta());
    } else return;
    event.preventDefault();
    return;
  }
  const run = name => { event.preventDefault(); editing.runAction(name); };
  if (ctrl && key === "z") return run(event.shiftKey ? "redo" : "undo");
  if (ctrl && key === "y") return run("redo");
  if (ctrl || event.altKey) return;
  if (key === "g") startModal("move", editing);
  else if (key === "r") startModal("rotate", editing);
  else if (key === "s") startModal("scale", editing);
  else if (key === "x" || key === "delete") return run("delete");
  else if (key === "d" && event.shiftKey) {
    // Blender's Shift+D: the copy, selected, follows the pointer until a click puts it down.
    event.preventDefault();
    Promise.resolve(editing.runAction("duplicate")).then(reply => { if (reply) startModal("move", editing); });
    return;
  }
  else if (key === "f") return run("frame-selection");
  else if (key === "home") return run("reset-view");
  else return;
  event.preventDefault();
}

export function initInput(editing) {
  overlay.addEventListener("contextmenu", e => e.preventDefault());
  overlay.addEventListener("pointerdown", e => {
    overlay.focus();
    if (modal) {
      endModal(editing, e.button === 0);
      return;
    }
    if (e.button !== 0 || gizmoHasPointer()) return;
    drag = { x: e.clientX, y: e.clientY, moved: false };
    overlay.setPointerCapture(e.pointerId);
  });
  overlay.addEventListener("pointermove", e => {
    pointer = pixelAt(e) || pointer;
    if (modal && pointer) {
      editing.gesture.move(modalDelta());
      return;
    }
    if (!drag) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    if (!drag.moved && Math.abs(dx) + Math.abs(dy) < 3) return;
    drag.moved = true;
    drag.x = e.clientX;
    drag.y = e.clientY;
    if (e.shiftKey) pan(dx, dy);
    else orbit(dx, dy);
  });
  overlay.addEventListener("pointerup", e => {
    if (drag && !drag.moved) {
      const pixel = pixelAt(e);
      if (pixel) {
        explainPixel(pixel);
        editing.selectAtPixel(pixel);
      }
    }
    drag = null;
  });
  overlay.addEventListener("wheel", e => {
    e.preventDefault();
    zoom(e.deltaY < 0);
  });
  window.addEventListener("keydown", e => onKey(e, editing));
  editing.actions["reset-view"] = resetView;
}
