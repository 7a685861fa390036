// What is drawn over the ray-traced view, in its camera (three.js on canvas#overlay): the
// selection's outline, which follows the object as it moves, and the gizmo that moves,
// rotates and scales it by dragging (three.js's TransformControls). The overlay's camera is
// the ray tracer's: the same eye, look, up and vertical angle, the view's aspect, so that
// what it draws lies on the object in the image (the pinhole model of SPEC §3 is a
// perspective projection, as three.js's).
//
// The gizmo moves a stand-in (proxy) placed at the selected object; a drag reports how the
// stand-in moved since the drag began, as a matrix in world coordinates, and the editing
// module (editing.js) turns that into the edit the server makes.
import {
  BoxGeometry, ConeGeometry, CylinderGeometry, EdgesGeometry, Group, LineBasicMaterial, LineSegments, Matrix4,
  Object3D, PerspectiveCamera, Scene, SphereGeometry, TorusGeometry, Vector3, WebGLRenderer, WireframeGeometry,
} from "three";
import { TransformControls } from "three/examples/jsm/controls/TransformControls.js";
import { emit, on, record, state } from "./state.js";
import { viewOfFrame } from "./view.js";

const canvas = document.getElementById("overlay");
const scene = new Scene();
const camera = new PerspectiveCamera(45, 4 / 3, 0.01, 1e5);
let renderer = null;  // null where the browser has no WebGL: the view works, without gizmo
let gizmo = null;
const proxy = new Object3D();
const outline = new Group();
let dragStart = null;  // the proxy's world matrix when a drag began
let redrawPending = false;

// The unit shapes of SPEC §2 as three.js draws them; each placement is outlined.
const torusGeometry = new TorusGeometry(0.375, 0.125, 8, 32).rotateX(Math.PI / 2);  // ring in the xz plane
const shapes = {
  cube: new EdgesGeometry(new BoxGeometry(1, 1, 1)),
  sphere: new WireframeGeometry(new SphereGeometry(0.5, 16, 8)),
  cylinder: new EdgesGeometry(new CylinderGeometry(0.5, 0.5, 1, 24, 1), 1),
  cone: new EdgesGeometry(new ConeGeometry(0.5, 1, 24, 1), 1),
  torus: new WireframeGeometry(torusGeometry),
};
const boundsGeometry = new EdgesGeometry(new BoxGeometry(1, 1, 1));
const outlineMaterial = new LineBasicMaterial({ color: 0xffa62b, depthTest: false, transparent: true, opacity: 0.9 });
const faintMaterial = new LineBasicMaterial({ color: 0xffa62b, depthTest: false, transparent: true, opacity: 0.35 });

// A 4×4 matrix from the server's rows ([[a, b, c, d], ...] or 12 or 16 numbers, row-major).
export function matrixFromRows(rows) {
  const v = rows.flat();
  const m = new Matrix4();
  m.set(v[0], v[1], v[2], v[3], v[4], v[5], v[6], v[7], v[8], v[9], v[10], v[11],
        v[12] ?? 0, v[13] ?? 0, v[14] ?? 0, v[15] ?? 1);
  return m;
}

export function rowsFromMatrix(m) {
  const e = m.elements;  // column-major
  return [0, 1, 2].map(r => [e[r], e[r + 4], e[r + 8], e[r + 12]]);
}

function redraw() {
  if (!renderer || redrawPending) return;
  redrawPending = true;
  requestAnimationFrame(() => {
    redrawPending = false;
    const began = performance.now();
    renderer.render(scene, camera);
    record.overlayDraws = (record.overlayDraws || 0) + 1;
    record.overlayMs = (record.overlayMs || 0) + performance.now() - began;
  });
}

// The overlay's camera is a view's (position, look, up, height_angle, size).
let shown = null;  // that view
function followCamera(view) {
  shown = view;
  const [x, y, z] = view.position, [lx, ly, lz] = view.look;
  camera.position.set(x, y, z);
  camera.up.set(...view.up);
  camera.lookAt(x + lx, y + ly, z + lz);
  camera.fov = view.height_angle || 45;
  camera.aspect = view.width / view.height;
  camera.updateProjectionMatrix();
  camera.updateMatrixWorld();
  redraw();
}

function fitCanvas() {
  if (!renderer) return;
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(canvas.clientWidth, canvas.clientHeight, false);
  redraw();
}

// The outline of every placement of the selected object (`worlds`: their object-to-world
// matrices); none when nothing is selected.
function showOutline(shape, worlds) {
  outline.clear();
  for (const world of worlds) {
    const line = shapes[shape] ? new LineSegments(shapes[shape], shape === "cube" ? outlineMaterial : faintMaterial)
                               : new LineSegments(boundsGeometry, outlineMaterial);
    line.matrixAutoUpdate = false;
    line.matrix.copy(world);
    outline.add(line);
  }
  redraw();
}

// Places the gizmo's stand-in at `world` (an object's): its origin, its axes' directions
// and lengths.
function placeProxy(world) {
  world.decompose(proxy.position, proxy.quaternion, proxy.scale);
  proxy.updateMatrixWorld(true);
}

// The selection changed or moved: its outline and, where the scene may be edited, the gizmo.
export function showSelection(selection) {
  const worlds = selection?.worlds?.map(matrixFromRows) ?? [];
  showOutline(selection?.type, worlds);
  if (!gizmo) return;
  if (worlds.length && state.editable) {
    if (!gizmo.dragging) placeProxy(worlds[0]);
    gizmo.attach(proxy);
  } else {
    gizmo.detach();
  }
  redraw();
}

// While a drag or a keyboard transform moves the selection, its outline moves with it
// (`delta`: the world-space change since it began) before the server answers.
export function moveOutline(delta, worlds) {
  outline.children.forEach((line, i) => line.matrix.multiplyMatrices(delta, matrixFromRows(worlds[i])));
  redraw();
}

export function setGizmoMode(mode) {
  if (!gizmo) return;
  gizmo.setMode(mode);
  // Moves along the world's axes (Blender's G); rotates and scales in the object's own.
  gizmo.setSpace(mode === "translate" ? "world" : "local");
  redraw();
}

// Whether a pointer press went to the gizmo (its handle under the pointer): then it is the
// gizmo's drag, not an orbit or a click.
export function gizmoHasPointer() {
  return Boolean(gizmo && (gizmo.dragging || gizmo.axis !== null));
}

// A world point's position in the view's pixels (x right, y down), and its depth in front
// of the camera (negative: behind it).
export function projectToView(point) {
  const p = new Vector3(...point).project(camera);
  return { x: (p.x + 1) / 2 * shown.width, y: (1 - p.y) / 2 * shown.height, inFront: p.z < 1 };
}
record.project = projectToView;  // where tests and bench/ find an object on the screen

// The point at the view's pixel (x, y) on the plane through `through` facing the camera.
export function unprojectToPlane(x, y, through) {
  const ndc = new Vector3(x / shown.width * 2 - 1, 1 - y / shown.height * 2, 0.5).unproject(camera);
  const eye = camera.position.clone(), direction = ndc.sub(eye).normalize();
  const normal = camera.getWorldDirection(new Vector3());
  const t = new Vector3(...through).sub(eye).dot(normal) / direction.dot(normal);
  return eye.add(direction.multiplyScalar(t)).toArray();
}

export function cameraAxes() {
  const forward = camera.getWorldDirection(new Vector3());
  const right = new Vector3().crossVectors(forward, camera.up).normalize();
  return { forward, right, up: new Vector3().crossVectors(right, forward) };
}

// Starts the overlay. `gesture` gets the gizmo's drags: begin(), move(delta), end(delta)
// with delta the world-space matrix taking the selection where it was to where it is.
export function initOverlay(gesture) {
  try {
    renderer = new WebGLRenderer({ canvas, alpha: true, antialias: false });
  } catch (e) {
    renderer = null;
    document.getElementById("help").textContent += " · no WebGL here: no gizmo (G, R, S still work)";
    return;
  }
  renderer.setClearColor(0x000000, 0);
  scene.add(outline, proxy);
  gizmo = new TransformControls(camera, canvas);
  gizmo.setSize(0.9);
  scene.add(gizmo.getHelper());
  setGizmoMode("translate");
  gizmo.addEventListener("change", redraw);
  const delta = () => new Matrix4().multiplyMatrices(proxy.matrixWorld, dragStart);
  gizmo.addEventListener("mouseDown", () => {
    proxy.updateMatrixWorld(true);
    dragStart = proxy.matrixWorld.clone().invert();
    gesture.begin();
  });
  gizmo.addEventListener("objectChange", () => {
    if (!dragStart) return;
    proxy.updateMatrixWorld(true);
    gesture.move(delta());
  });
  gizmo.addEventListener("mouseUp", () => {
    if (!dragStart) return;
    proxy.updateMatrixWorld(true);
    const change = delta();
    dragStart = null;
    gesture.end(change);
  });
  new ResizeObserver(fitCanvas).observe(canvas);
  fitCanvas();
  // In the camera of the frame shown (view.js viewOfFrame), which lags the pointer.
  on("frame", f => followCamera(viewOfFrame(f)));
  followCamera(state.view);
  emit("overlay", { gizmo });
}
