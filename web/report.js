// The run report's page (docs/report.md): a 3D player of the run and plots of its energy.csv, from
// the data that src/run/run_report.cpp writes into the page (the element #run-data). three.js
// draws the sheet, each frame with the mesh of that frame's topology (torn sheets split), the
// anchors holding at that frame and the obstacles where they are at that frame.
//
// The page answers the tests (tests/report) through #report-status, a JSON line written once it
// has drawn: the frame count, the frame shown, the errors seen, and with "#probe" in the address
// the positions drawn. "#frame=last" (or "#frame=K") opens the player at that frame.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";

const data = JSON.parse(document.getElementById("run-data").textContent);

function decode(base64, Type) {
  const bytes = Uint8Array.from(atob(base64), (c) => c.charCodeAt(0));
  return new Type(bytes.buffer);
}

const positions = decode(data.positions, Float32Array);
const frameCount = data.times.length;
const epochs = data.epochs.map((epoch) => ({ first: epoch.first, triangles: decode(epoch.triangles, Uint32Array) }));

// ---------------------------------------------------------------------------------------------
// The 3D view.

const canvas = document.getElementById("view");
const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
renderer.setPixelRatio(window.devicePixelRatio || 1);
const scene = new THREE.Scene();
scene.background = new THREE.Color(0xdfe6ec);
scene.add(new THREE.HemisphereLight(0xffffff, 0x8d9aa6, 1.6));
const sun = new THREE.DirectionalLight(0xffffff, 1.8);
sun.position.set(2, 4, 3);
scene.add(sun);

// The sheet: one BufferGeometry whose positions change every frame and whose index changes with
// the topology (an epoch starts at each frame where connectors broke).
const sheetGeometry = new THREE.BufferGeometry();
const sheet = new THREE.Mesh(
  sheetGeometry,
  new THREE.MeshStandardMaterial({ color: 0x3d7cc9, side: THREE.DoubleSide, roughness: 0.75, metalness: 0.0 }),
);
scene.add(sheet);

// The bounds of every frame, for the camera and for the size of planes and markers.
const low = new THREE.Vector3(Infinity, Infinity, Infinity);
const high = new THREE.Vector3(-Infinity, -Infinity, -Infinity);
for (let i = 0; i < positions.length; i += 3) {
  low.min(new THREE.Vector3(positions[i], positions[i + 1], positions[i + 2]));
  high.max(new THREE.Vector3(positions[i], positions[i + 1], positions[i + 2]));
}
const centre = low.clone().add(high).multiplyScalar(0.5);
const extent = Math.max(high.clone().sub(low).length(), 1e-6);

const anchorRadius = Math.max(0.35 * data.spacing, 0.004 * extent);
const anchorMarkers = new THREE.InstancedMesh(
  new THREE.SphereGeometry(anchorRadius, 16, 12),
  new THREE.MeshStandardMaterial({ color: 0xd8453b }),
  Math.max(1, data.anchors.length),
);
anchorMarkers.count = 0;
scene.add(anchorMarkers);

const obstacleMaterial = new THREE.MeshStandardMaterial({
  color: 0x9aa3ab, roughness: 0.9, side: THREE.DoubleSide, transparent: true, opacity: 0.85,
});
const vec = (a) => new THREE.Vector3(a[0], a[1], a[2]);
const obstacles = data.colliders.map((collider) => {
  let mesh;
  let base = new THREE.Vector3();
  if (collider.shape === "plane") {
    const size = 3 * extent;
    mesh = new THREE.Mesh(new THREE.PlaneGeometry(size, size), obstacleMaterial);
    mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 0, 1), vec(collider.normal).normalize());
    // The square is centred where the sheet's centre projects onto the plane.
    const normal = vec(collider.normal).normalize();
    base = centre.clone().sub(normal.clone().multiplyScalar(centre.clone().sub(vec(collider.point)).dot(normal)));
  } else if (collider.shape === "sphere") {
    mesh = new THREE.Mesh(new THREE.SphereGeometry(collider.radius, 48, 24), obstacleMaterial);
    base = vec(collider.center);
  } else if (collider.shape === "box") {
    const h = collider.half_extents;
    mesh = new THREE.Mesh(new THREE.BoxGeometry(2 * h[0], 2 * h[1], 2 * h[2]), obstacleMaterial);
    base = vec(collider.center);
  } else if (collider.shape === "capsule") {
    const a = vec(collider.a);
    const b = vec(collider.b);
    const axis = b.clone().sub(a);
    mesh = new THREE.Mesh(new THREE.CapsuleGeometry(collider.radius, axis.length(), 8, 24), obstacleMaterial);
    if (axis.length() > 0) mesh.quaternion.setFromUnitVectors(new THREE.Vector3(0, 1, 0), axis.clone().normalize());
    base = a.clone().add(b).multiplyScalar(0.5);
  } else {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute("position", new THREE.BufferAttribute(decode(collider.vertices, Float32Array), 3));
    geometry.setIndex(new THREE.BufferAttribute(decode(collider.triangles, Uint32Array), 1));
    geometry.computeVertexNormals();
    mesh = new THREE.Mesh(geometry, obstacleMaterial);
  }
  scene.add(mesh);
  return { mesh, base, offsets: decode(collider.offsets, Float32Array) };
});

const camera = new THREE.PerspectiveCamera(40, 1, extent * 1e-3, extent * 100);
camera.position.copy(centre).add(new THREE.Vector3(0.9, 0.75, 1.3).multiplyScalar(extent));
const controls = new OrbitControls(camera, canvas);
controls.target.copy(centre);
controls.update();

function resize() {
  const width = canvas.clientWidth;
  const height = canvas.clientHeight;
  if (canvas.width !== Math.round(width * renderer.getPixelRatio()) || camera.aspect !== width / height) {
    renderer.setSize(width, height, false);
    camera.aspect = width / height;
    camera.updateProjectionMatrix();
  }
}

function draw() {
  resize();
  renderer.render(scene, camera);
}
controls.addEventListener("change", draw);
window.addEventListener("resize", draw);

// ---------------------------------------------------------------------------------------------
// Frames.

let shown = -1;
let epochShown = -1;

function epochOf(frame) {
  let e = 0;
  while (e + 1 < epochs.length && epochs[e + 1].first <= frame) e += 1;
  return e;
}

function framePositions(frame) {
  const start = data.vertex_offsets[frame];
  return positions.subarray(start, start + 3 * data.vertex_counts[frame]);
}

const scrub = document.getElementById("scrub");
const label = document.getElementById("frame-label");
scrub.max = String(frameCount - 1);

function setFrame(frame) {
  frame = Math.max(0, Math.min(frameCount - 1, frame));
  shown = frame;
  const epoch = epochOf(frame);
  const vertices = framePositions(frame);
  const attribute = sheetGeometry.getAttribute("position");
  if (!attribute || attribute.array.length !== vertices.length) {
    sheetGeometry.setAttribute("position", new THREE.BufferAttribute(new Float32Array(vertices), 3));
  } else {
    attribute.array.set(vertices);
    attribute.needsUpdate = true;
  }
  if (epoch !== epochShown) {
    sheetGeometry.setIndex(new THREE.BufferAttribute(epochs[epoch].triangles, 1));
    epochShown = epoch;
  }
  sheetGeometry.computeVertexNormals();
  sheetGeometry.computeBoundingSphere();

  const time = data.times[frame];
  const matrix = new THREE.Matrix4();
  let live = 0;
  for (const anchor of data.anchors) {
    if (anchor.release_time !== null && time >= anchor.release_time) continue;
    const p = 3 * anchor.particle;
    matrix.makeTranslation(vertices[p], vertices[p + 1], vertices[p + 2]);
    anchorMarkers.setMatrixAt(live, matrix);
    live += 1;
  }
  anchorMarkers.count = live;
  anchorMarkers.instanceMatrix.needsUpdate = true;
  for (const obstacle of obstacles) {
    const o = obstacle.offsets;
    obstacle.mesh.position.copy(obstacle.base).add(new THREE.Vector3(o[3 * frame], o[3 * frame + 1], o[3 * frame + 2]));
  }

  scrub.value = String(frame);
  label.textContent = `frame ${data.frames[frame]} of ${data.total_frames - 1}, t = ${time.toFixed(3)} s`;
  for (const plot of plots) plot.moveCursor(time);
  draw();
}

let playing = false;
let playStart = 0;
let playFrom = 0;
const playButton = document.getElementById("play");

function tick(now) {
  if (!playing) return;
  const elapsed = (now - playStart) / 1000;
  let frame = shown;
  while (frame + 1 < frameCount && data.times[frame + 1] - data.times[playFrom] <= elapsed) frame += 1;
  if (frame !== shown) setFrame(frame);
  if (frame + 1 >= frameCount) {
    setPlaying(false);
    return;
  }
  requestAnimationFrame(tick);
}

function setPlaying(on) {
  playing = on;
  playButton.textContent = on ? "Pause" : "Play";
  if (on) {
    if (shown + 1 >= frameCount) setFrame(0);
    playFrom = shown;
    playStart = performance.now();
    requestAnimationFrame(tick);
  }
}
playButton.addEventListener("click", () => setPlaying(!playing));
scrub.addEventListener("input", () => {
  setPlaying(false);
  setFrame(Number(scrub.value));
});

// ---------------------------------------------------------------------------------------------
// Plots of energy.csv: SVG polylines against time, a cursor at the frame shown.

function parseCsv(text) {
  const lines = text.trim().split("\n");
  const header = lines[0].split(",");
  const columns = Object.fromEntries(header.map((name) => [name, []]));
  for (const line of lines.slice(1)) {
    line.split(",").forEach((cell, i) => columns[header[i]].push(Number(cell)));
  }
  return columns;
}

const palette = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"];
const svgNamespace = "http://www.w3.org/2000/svg";

function svgElement(name, attributes, parent) {
  const element = document.createElementNS(svgNamespace, name);
  for (const [key, value] of Object.entries(attributes)) element.setAttribute(key, value);
  parent.appendChild(element);
  return element;
}

function formatNumber(value) {
  if (value === 0) return "0";
  const magnitude = Math.abs(value);
  return magnitude >= 1e4 || magnitude < 1e-2 ? value.toExponential(2) : value.toPrecision(3);
}

function linePlot(title, unit, time, series) {
  const section = document.createElement("div");
  section.className = "plot";
  const heading = document.createElement("h3");
  heading.style.cssText = "font-size: 13px; margin: 0 0 2px";
  heading.textContent = unit ? `${title} (${unit})` : title;
  section.appendChild(heading);
  const width = 600;
  const height = 190;
  const left = 62;
  const right = 8;
  const top = 8;
  const bottom = 22;
  const svg = svgElement("svg", { viewBox: `0 0 ${width} ${height}`, preserveAspectRatio: "none" }, section);
  let yLow = Infinity;
  let yHigh = -Infinity;
  for (const s of series) {
    for (const v of s.values) {
      if (Number.isFinite(v)) {
        yLow = Math.min(yLow, v);
        yHigh = Math.max(yHigh, v);
      }
    }
  }
  if (!Number.isFinite(yLow)) {
    yLow = 0;
    yHigh = 1;
  }
  if (yHigh === yLow) {
    yHigh += Math.max(1e-12, Math.abs(yHigh) * 0.1);
    yLow -= Math.max(1e-12, Math.abs(yLow) * 0.1);
  }
  const tLow = time[0];
  const tHigh = time[time.length - 1] > tLow ? time[time.length - 1] : tLow + 1;
  const x = (t) => left + ((t - tLow) / (tHigh - tLow)) * (width - left - right);
  const y = (v) => top + ((yHigh - v) / (yHigh - yLow)) * (height - top - bottom);
  svgElement("rect", { x: left, y: top, width: width - left - right, height: height - top - bottom, fill: "#fbfcfd",
                       stroke: "#c9d2da" }, svg);
  for (const [value, anchor] of [[yHigh, "hanging"], [yLow, "auto"]]) {
    const text = svgElement("text", { x: left - 4, y: y(value), "text-anchor": "end", "dominant-baseline": anchor }, svg);
    text.textContent = formatNumber(value);
  }
  if (yLow < 0 && yHigh > 0) {
    svgElement("line", { x1: left, x2: width - right, y1: y(0), y2: y(0), stroke: "#c9d2da" }, svg);
  }
  for (const [t, anchor] of [[tLow, "start"], [tHigh, "end"]]) {
    const text = svgElement("text", { x: x(t), y: height - 6, "text-anchor": anchor }, svg);
    text.textContent = `${formatNumber(t)} s`;
  }
  series.forEach((s, i) => {
    const points = [];
    s.values.forEach((v, k) => {
      if (Number.isFinite(v) && Number.isFinite(time[k])) points.push(`${x(time[k]).toFixed(2)},${y(v).toFixed(2)}`);
    });
    svgElement("polyline", { points: points.join(" "), fill: "none", stroke: palette[i % palette.length],
                             "stroke-width": 1.6, "vector-effect": "non-scaling-stroke" }, svg);
  });
  const cursor = svgElement("line", { y1: top, y2: height - bottom, stroke: "#1d2733", "stroke-dasharray": "3 3" }, svg);
  const legend = document.createElement("div");
  legend.className = "legend";
  series.forEach((s, i) => {
    const item = document.createElement("span");
    item.style.setProperty("--colour", palette[i % palette.length]);
    item.textContent = s.name;
    legend.appendChild(item);
  });
  section.appendChild(legend);
  document.getElementById("plots").appendChild(section);
  return {
    element: section,
    moveCursor(t) {
      cursor.setAttribute("x1", x(t));
      cursor.setAttribute("x2", x(t));
    },
  };
}

const columns = parseCsv(data.energy_csv);
const csvTime = columns.time;
function present(names) {
  return names.filter((name) => name in columns).map((name) => ({ name, values: columns[name] }));
}
// The mean step of each frame: the frame's time over the steps accepted in it.
const meanStep = csvTime.map((t, k) => {
  if (k === 0) return NaN;
  const steps = columns.accepted_steps[k] - columns.accepted_steps[k - 1];
  return steps > 0 ? (t - csvTime[k - 1]) / steps : NaN;
});
const rejected = csvTime.map((t, k) => (k === 0 ? NaN : columns.rejected_steps[k] - columns.rejected_steps[k - 1]));
const plots = [
  linePlot("Energy", "J", csvTime,
           present(["kinetic", "gravitational", "connector", "radial_adjacent", "radial_opposite", "total"])),
  linePlot("Work done on the sheet", "J", csvTime,
           present(["damping_work", "drag_work", "anchor_work", "plastic_work", "fracture_work", "contact_work"])),
  linePlot("Energy balance error", "J", csvTime, present(["balance_error"])),
  linePlot("Mean step size", "s", csvTime, [{ name: "accepted step", values: meanStep }]),
  linePlot("Rejected steps per frame", "", csvTime, [{ name: "rejected", values: rejected }]),
  linePlot("Events", "", csvTime, present(["broken_connectors", "contacts", "self_contacts"])),
  linePlot("Permanent deformation", "", csvTime, present(["max_plastic_strain", "max_rest_angle_change"])),
];

// ---------------------------------------------------------------------------------------------
// Title and summary.

document.getElementById("title").textContent = `${data.name}: ${data.summary.status ?? ""}`;
document.getElementById("description").textContent = data.description;
const table = document.getElementById("summary-table");
function addRows(prefix, value) {
  if (value !== null && typeof value === "object" && !Array.isArray(value)) {
    for (const [key, inner] of Object.entries(value)) addRows(prefix ? `${prefix}.${key}` : key, inner);
    return;
  }
  const row = table.insertRow();
  row.insertCell().textContent = prefix;
  row.insertCell().textContent = typeof value === "number" ? formatNumber(value) : JSON.stringify(value);
}
addRows("", data.summary);
if (data.frames.length < data.total_frames) {
  const note = document.getElementById("stride-note");
  note.hidden = false;
  note.textContent = `The player holds ${data.frames.length} of the run's ${data.total_frames} frames ` +
    `(every ${data.frame_stride}th and the last), to keep the page below its size limit.`;
}

// ---------------------------------------------------------------------------------------------
// Start, and answer the tests.

const hash = new URLSearchParams(location.hash.slice(1));
const requested = hash.get("frame");
setFrame(requested === "last" ? frameCount - 1 : Number(requested ?? 0) || 0);
// The pieces of the sheet drawn: connected components of the mesh's triangles (union-find).
function pieces(epoch, vertexCount) {
  const parent = Int32Array.from({ length: vertexCount }, (_, i) => i);
  const find = (i) => {
    while (parent[i] !== i) i = parent[i] = parent[parent[i]];
    return i;
  };
  const triangles = epochs[epoch].triangles;
  for (let t = 0; t < triangles.length; t += 3) {
    parent[find(triangles[t])] = find(triangles[t + 1]);
    parent[find(triangles[t + 1])] = find(triangles[t + 2]);
  }
  const roots = new Set();
  for (let t = 0; t < triangles.length; t += 1) roots.add(find(triangles[t]));
  return roots.size;
}
const rect = (element) => {
  const r = element.getBoundingClientRect();
  return [Math.round(r.left), Math.round(r.top + window.scrollY), Math.round(r.width), Math.round(r.height)];
};
const status = {
  ready: true,
  frames: frameCount,
  total_frames: data.total_frames,
  frame: shown,
  vertices: data.vertex_counts[shown],
  triangles: epochs[epochShown].triangles.length / 3,
  pieces: pieces(epochShown, data.vertex_counts[shown]),
  anchors_shown: anchorMarkers.count,
  view: rect(canvas),
  plots: plots.map((plot) => rect(plot.element.querySelector("svg"))),
  errors: window.reportErrors,
};
if (hash.has("probe")) status.positions = Array.from(framePositions(shown));
document.getElementById("report-status").textContent = JSON.stringify(status);
window.clothsimReport = { setFrame, frameCount };
