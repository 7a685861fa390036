// The properties panel: the selection's fields, as the server's field table describes them
// (editing.js turns its answer into groups of fields). Each input carries data-field, the
// field's scenefile name. A value is sent when the user commits it (a colour as it is
// picked, a number when typed); a refused value shows the server's error beside its field
// and the field goes back to the value the scene holds. Nothing else is blocked: every
// other field stays editable, and the next edit is judged on its own.
import { latestOnly } from "./api.js";
import { record } from "./state.js";

const fieldsBox = document.getElementById("fields");
let shown = { key: null, rows: new Map() };  // what the panel shows: its selection and rows by field
let gestures = 0;  // colour picks so far: each one's action id differs

const toHex = c => "#" + c.map(v => Math.round(Math.min(1, Math.max(0, v)) * 255).toString(16).padStart(2, "0")).join("");
const fromHex = h => [1, 3, 5].map(i => parseInt(h.substr(i, 2), 16) / 255);

// Inputs for one field's value: a colour picker, numbers (one, or three for a vector), a
// list of choices or a line of text. Each reads and shows the field's value.
function inputsFor(field) {
  const make = (type) => {
    const input = document.createElement("input");
    input.type = type;
    input.dataset.field = field.name;
    input.title = field.help || "";
    return input;
  };
  if (field.kind === "color") {
    const input = make("color");
    return { inputs: [input], read: () => fromHex(input.value), show: v => { input.value = toHex(v); } };
  }
  if (field.kind === "choice") {
    const select = document.createElement("select");
    select.dataset.field = field.name;
    for (const choice of field.choices || []) select.add(new Option(choice));
    return { inputs: [select], read: () => select.value, show: v => { select.value = v; } };
  }
  if (field.kind === "text" || field.kind === "file") {
    const input = make("text");
    if (field.kind === "file") input.placeholder = "a file beside the scene";
    return { inputs: [input], read: () => input.value, show: v => { input.value = v; } };
  }
  if (field.kind === "transforms") return transformInputs(field, make);
  const count = field.kind === "vector" ? 3 : field.kind === "vector4" ? 4 : 1;
  const inputs = Array.from({ length: count }, (_, i) => {
    const input = make("number");
    input.step = field.step ?? "any";
    if (field.min !== undefined && count === 1) input.min = field.min;
    if (field.max !== undefined && count === 1) input.max = field.max;
    if (count > 1) input.dataset.component = String(i);
    return input;
  });
  return {
    inputs,
    read: () => count === 1 ? Number(inputs[0].value) : inputs.map(i => Number(i.value)),
    show: v => (count === 1 ? [v] : v).forEach((c, i) => { inputs[i].value = String(+c.toPrecision(7)); }),
  };
}

// A transblock's transforms (translate, rotate, scale: their numbers; a matrix: its 12),
// each number an input with data-op (the transform's place) and data-component.
function transformInputs(field, make) {
  const kinds = field.value.map(op => op.kind);
  const inputs = [];
  field.value.forEach((op, i) => op.v.forEach((_, k) => {
    const input = make("number");
    input.step = "any";
    input.dataset.op = String(i);
    input.dataset.component = String(k);
    input.title = `${i + 1}. ${op.kind}`;
    inputs.push(input);
  }));
  const at = (i, k) => inputs.find(input => input.dataset.op === String(i) && input.dataset.component === String(k));
  return {
    inputs,
    read: () => kinds.map((kind, i) => ({ kind, v: field.value[i].v.map((_, k) => Number(at(i, k).value)) })),
    show: ops => ops.forEach((op, i) => op.v.forEach((c, k) => { at(i, k).value = String(+c.toPrecision(7)); })),
  };
}

// One field's row: its label, its inputs, and the line its refusal is shown in.
function fieldRow(field, commit) {
  const row = document.createElement("div");
  row.className = "field";
  const label = document.createElement("span");
  label.textContent = field.label || field.name.replaceAll("_", " ");
  label.title = field.help || "";
  const { inputs, read, show } = inputsFor(field);
  const box = document.createElement("span");
  box.className = "inputs";
  box.append(...inputs);
  const error = document.createElement("div");
  error.className = "field-error";
  row.append(label, box, error);
  let held = field.value;  // what the scene holds
  show(held);
  // The scene changed (an undo, another page): the field shows its new value, unless the
  // user is in the middle of typing in it.
  row.update = (value) => {
    held = value;
    if (!inputs.includes(document.activeElement)) show(value);
  };
  // A colour being picked sends a value for each move of the picker, all of one gesture
  // (one undo step) until the picker is closed ("change"); the latest alone waits while one
  // is in flight.
  let gesture = null;
  const sendLatest = latestOnly(({ value, action }) => commit(field, value, action));
  const send = async (event) => {
    if (inputs.some(i => i.type === "number" && i.value === "")) return;  // a number being typed
    const value = read();
    let action;
    if (field.kind === "color") {
      action = gesture ??= `pick-${field.name}-${Date.now().toString(36)}-${++gestures}`;
      if (event.type === "change") gesture = null;
    }
    const answer = await sendLatest({ value, action });
    if (!answer) return;  // overtaken by a later value of the same gesture
    const { ok, status, error: why } = answer;
    if (ok) {
      held = value;
      error.textContent = "";
      row.classList.remove("refused");
    } else {
      error.textContent = why;
      row.classList.add("refused");
      show(held);
      record.editErrors.push({ field: field.name, status, error: why });
    }
  };
  // A colour is sent as it is picked (the server renders the latest); a number or text
  // when it is committed (Enter, leaving the field, the arrows of the spinner).
  for (const input of inputs) {
    input.addEventListener("change", send);
    if (field.kind === "color") input.addEventListener("input", send);
  }
  return row;
}

// A row stays for a field of the same name and shape (a transblock's transforms of the
// same kinds); another shape is a new row.
const rowKey = field => `${field.name}/${field.index ?? ""}/${field.kind}` +
  (field.kind === "transforms" ? "/" + field.value.map(op => `${op.kind}${op.v.length}`).join(",") : "");

// Shows `groups` ([{ title, fields: [...] }]) and sends each committed value through
// `commit(field, value)`, which answers { ok, status, error }. `key` names what the fields
// are of: shown again for the same key with the same fields, the rows stay (a refusal's
// message stays beside its field) and only their values change.
export function showFields(groups, commit, key = null) {
  const fields = groups.flatMap(g => g.fields);
  if (key !== null && key === shown.key && fields.length === shown.rows.size &&
      fields.every(f => shown.rows.has(rowKey(f)))) {
    for (const f of fields) shown.rows.get(rowKey(f)).update(f.value);
    return;
  }
  shown = { key, rows: new Map() };
  fieldsBox.replaceChildren();
  for (const group of groups) {
    const set = document.createElement("fieldset");
    const legend = document.createElement("legend");
    legend.textContent = group.title;
    set.append(legend);
    if (group.note) {
      const note = document.createElement("div");
      note.textContent = group.note;
      set.append(note);
    }
    for (const field of group.fields) {
      const row = fieldRow(field, commit);
      shown.rows.set(rowKey(field), row);
      set.append(row);
    }
    fieldsBox.append(set);
  }
}
