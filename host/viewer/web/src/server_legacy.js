// The editor's routes of a viewer without the one edit model (before docs/modeler-protocol.md
// is served): POST /edit of an object's material or its transblock's transforms, or a
// light's fields; GET /pick, /object and /state. It has no tree of the scene, no adds,
// deletes or duplicates, and merges quick edits of one thing into one undo step; the
// outline lists the camera, the lights and the objects selected so far.
import { getJson, postJson } from "./api.js";
import { rowsFromMatrix } from "./overlay.js";
import { composeOps } from "./transforms.js";

const seenObjects = new Map();  // id -> object description: the objects selected so far

async function lights() {
  const { answer } = await getJson("/state");
  return answer.lights || [];
}

function objectSelection(o) {
  seenObjects.set(o.object, o);
  const m = o.material;
  const material = ["diffuse", "ambient", "specular", "reflective", "transparent", "emissive"]
    .map(name => ({ name, kind: "color", value: m[name] }))
    .concat(["shininess", "ior", "blend"].map(name => ({ name, kind: "number", value: m[name] })));
  const transform = o.transform.map((op, i) => ({
    name: op.kind, label: `${i + 1}. ${op.kind}`, kind: op.v.length === 4 ? "vector4" : op.v.length === 3 ? "vector" : "text",
    value: op.v.length <= 4 ? op.v : op.v.join(" "), index: i,
  }));
  const note = o.block_objects > 1 ? `its transblock holds ${o.block_objects} objects: they move together` : "";
  return { ...o, node: `object-${o.object}`, kind: "object",
           description: `${o.type} ${o.path} (object ${o.object}, line ${o.line})`,
           worlds: [rowsFromMatrix(composeOps(o.transform))],
           groups: [{ title: "material", fields: material }, { title: "transform", fields: transform, note }] };
}

function lightSelection(index, l) {
  const fields = [{ name: "color", kind: "color", value: l.color }];
  const uses = { point: ["position", "attenuation"], directional: ["direction"],
                 spot: ["position", "direction", "attenuation", "angle", "penumbra"],
                 area: ["position", "direction", "attenuation", "width", "height"] };
  for (const name of uses[l.type] || [])
    fields.push({ name, kind: Array.isArray(l[name]) ? "vector" : "number", value: l[name] });
  return { node: `light-${index}`, kind: "light", light: index, type: l.type, description: `light ${index} (${l.type})`,
           groups: [{ title: `light ${index} (${l.type})`, fields }] };
}

export const legacyServer = {
  name: "legacy",
  available: async () => true,
  async outline() {
    const nodes = [{ node: "camera", kind: "camera", text: "the file's camera", depth: 0 }];
    (await lights()).forEach((l, i) => nodes.push({ node: `light-${i}`, kind: "light", text: `${l.type} light ${i}`, depth: 0 }));
    for (const [object, o] of seenObjects) nodes.push({ node: `object-${object}`, kind: o.type, text: o.path, depth: 0 });
    return nodes;
  },
  async load(id) {
    const [kind, number] = id.split("-");
    if (kind === "light") {
      const all = await lights();
      return Number(number) < all.length ? lightSelection(Number(number), all[Number(number)]) : null;
    }
    if (kind !== "object") return null;
    const { ok, answer } = await getJson(`/object?id=${number}`);
    return ok ? objectSelection(answer) : null;
  },
  async pick(x, y) {
    const { answer } = await getJson(`/pick?x=${x}&y=${y}`);
    return answer.object === null || answer.object === undefined ? { error: answer.error } : objectSelection(answer);
  },
  commit(s, field, value) {
    if (s.light !== undefined) return postJson("/edit", { light: s.light, [field.name]: value });
    if (field.index === undefined) return postJson("/edit", { object: s.object, material: { [field.name]: value } });
    const ops = s.transform.map(op => ({ kind: op.kind, v: [...op.v] }));
    ops[field.index].v = value;
    return postJson("/edit", { object: s.object, transform: ops });
  },
  // A drag sets the transblock's transforms to the one matrix of where it is now.
  move(s, rows) {
    const m = [...rows[0], ...rows[1], ...rows[2]];
    return postJson("/edit", { object: s.object, transform: [{ kind: "matrix", v: m }] });
  },
  revert(s) {
    return postJson("/edit", { object: s.object, transform: s.transform });
  },
  newAction: () => null,
  operation: () => null,
  run: async () => null,
  editorOf: answer => answer,
  outlineChanged: () => false,
};
