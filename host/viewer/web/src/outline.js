// The outline of the scene: its tree (the camera, the lights, the trees, their transblocks,
// objects and master placements) as a list the selection is shared with: a click on an
// entry selects what it names, as a click in the view does, and the selected entry is
// highlighted whichever way it was selected. Each entry carries data-node (the server's
// node id), names its shape or kind in its text (the kind in the words of the scene's format,
// the server's label: "transblock" in an XML scene, "group" in a JSON one) and its place in the
// file as its tooltip ("root/transblock[1]/object[0]", "groups[1].primitives[0]").
const outlineBox = document.getElementById("outline");
let entries = new Map();  // node id -> element
let shownNodes = "";       // the nodes shown, as JSON

// nodes: [{ node, kind, label, text, path, depth }] in the tree's order; onSelect(node) for a click. The
// same nodes again leave the entries as they are (a click on one is never lost to a
// rebuild).
export function showOutline(nodes, onSelect, selectedNode) {
  const json = JSON.stringify(nodes);
  if (json === shownNodes) return highlight(selectedNode);
  shownNodes = json;
  outlineBox.replaceChildren();
  entries = new Map();
  for (const node of nodes) {
    const entry = document.createElement("div");
    entry.className = "node " + (node.depth <= 5 ? `depth-${node.depth}` : "deeper");
    entry.dataset.node = node.node;
    const kind = document.createElement("span");
    kind.className = "kind";
    // An object's text is its shape already; other entries say what they are first.
    kind.textContent = node.kind === "object" ? "" : node.label;
    entry.append(kind, node.text);
    entry.title = node.path || "";
    entry.addEventListener("click", () => onSelect(node));
    outlineBox.append(entry);
    entries.set(String(node.node), entry);
  }
  highlight(selectedNode);
}

export function highlight(node) {
  for (const [id, entry] of entries) entry.classList.toggle("selected", node !== null && node !== undefined && id === String(node));
  const entry = entries.get(String(node));
  if (entry) entry.scrollIntoView({ block: "nearest" });
}
