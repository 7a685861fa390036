// The view's camera, moved by the pointer: orbit about the point it looks at (position +
// look), pan across the view, zoom along look; framing a sphere (F) and the file's camera
// (Home).
import { add, cross, len, norm, rotate, scale, sub } from "./vec.js";
import { state } from "./state.js";
import { sendView } from "./view.js";

export function orbit(dx, dy) {
  const view = state.view;
  const target = add(view.position, view.look);
  let offset = sub(view.position, target);
  const up = norm(view.up), right = norm(cross(view.look, view.up));
  offset = rotate(offset, up, -dx * 0.01);
  const tilted = rotate(offset, right, -dy * 0.01);
  if (len(cross(norm(tilted), up)) > 0.05) offset = tilted;  // never over the pole
  sendView({ position: add(target, offset), look: scale(offset, -1) });
}

export function pan(dx, dy) {
  const view = state.view;
  const right = norm(cross(view.look, view.up)), up = norm(cross(right, view.look));
  const k = len(view.look) * 0.002, move = add(scale(right, -dx * k), scale(up, dy * k));
  sendView({ position: add(view.position, move) });
}

export function zoom(towards) {
  const view = state.view, step = towards ? 0.1 : -0.1;
  sendView({ position: add(view.position, scale(view.look, step)), look: scale(view.look, 1 - step) });
}

// Looks at `center` from the present direction, from far enough that a sphere of `radius`
// about it fills about two thirds of the view's height.
export function frameSphere(center, radius) {
  const view = state.view;
  const halfAngle = (view.height_angle || 45) * Math.PI / 360;
  const distance = Math.max(radius, 1e-3) / Math.sin(halfAngle) * 1.5;
  const look = scale(norm(view.look), distance);
  sendView({ position: sub(center, look), look });
}

export function resetView() {
  if (state.fileCamera) sendView({ ...state.fileCamera });
}
