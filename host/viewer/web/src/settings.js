// The render settings' controls, made from the server's table (/settings): a checkbox for a
// switch, a list for a choice, a number field with the setting's range otherwise. The size,
// depth and depth of field are laid out in the page itself.
import { getJson } from "./api.js";
import { sendView } from "./view.js";

const notes = { aa: " once the view rests (while it moves: one sample a pixel)" };
const controlsBox = document.getElementById("controls");
const dof = document.getElementById("dof"), depth = document.getElementById("depth");
let controls = [];

function makeControl(setting) {
  const label = document.createElement("label"), name = setting.name.replaceAll("_", " ");
  label.title = setting.help + (notes[setting.name] || "");
  let input;
  if (setting.kind === "switch") {
    input = document.createElement("input");
    input.type = "checkbox";
    label.append(input, name);
  } else {
    if (setting.kind === "choice") {
      input = document.createElement("select");
      for (const choice of setting.choices) input.add(new Option(choice));
    } else {
      input = document.createElement("input");
      input.type = "number";
      input.min = setting.min;
      input.max = setting.max;
      input.step = setting.kind === "integer" ? 1 : "any";
    }
    label.append(name + " ", input);
  }
  input.id = setting.name;
  input.addEventListener("change", () => sendView(settingsFromControls()));
  controlsBox.append(label);
  return { setting, input };
}

function value({ setting, input }) {
  if (setting.kind === "switch") return input.checked;
  if (setting.kind === "choice") return input.value;
  return Number(input.value);
}

function show({ setting, input }, v) {
  if (setting.kind === "switch") input.checked = v;
  else input.value = v;
}

function settingsFromControls() {
  const settings = { dof: dof.value, depth: Number(depth.value) };
  for (const control of controls) settings[control.setting.name] = value(control);
  return settings;
}

export async function initSettings(view) {
  const { answer } = await getJson("/settings");
  controls = answer.map(makeControl);
  for (const control of controls) show(control, view[control.setting.name]);
  dof.value = view.dof;
  depth.value = view.depth;
  for (const input of [dof, depth]) input.addEventListener("change", () => sendView(settingsFromControls()));
}
