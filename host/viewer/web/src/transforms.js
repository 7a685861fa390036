// A transblock's transforms as the scenefile writes them (translate, rotate about an axis
// by degrees, scale, a 3×4 matrix), composed as the loader composes them: T1 · T2 · … · Tn,
// the last applied first (scene/scene_document.h).
import { Matrix4, Vector3 } from "three";

export function opMatrix(op) {
  const v = op.v, m = new Matrix4();
  if (op.kind === "translate") return m.makeTranslation(v[0], v[1], v[2]);
  if (op.kind === "scale") return m.makeScale(v[0], v[1], v[2]);
  if (op.kind === "rotate") return m.makeRotationAxis(new Vector3(v[0], v[1], v[2]).normalize(), v[3] * Math.PI / 180);
  if (op.kind === "matrix") return m.set(...v.slice(0, 12), 0, 0, 0, 1);
  return m;
}

export function composeOps(ops) {
  const m = new Matrix4();
  for (const op of ops) m.multiply(opMatrix(op));
  return m;
}

// A matrix as the 12 numbers of a <matrix> transform (its first three rows).
export function matrixOp(m) {
  const e = m.elements;  // column-major
  return { kind: "matrix", v: [0, 1, 2].flatMap(r => [e[r], e[r + 4], e[r + 8], e[r + 12]]) };
}
