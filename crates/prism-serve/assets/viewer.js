// prism's live viewer page. The server sends JSON text (hello, state, error) and binary
// messages: a 4-byte little-endian header length, a JSON header, then RGBA pixels (a frame)
// or a PNG file (a saved image). The page sends JSON text: move, camera, reset_camera, set,
// save (docs/viewer.md). Camera moves are summed while one is in flight and sent when a
// frame shows it, so a fast mouse never queues stale moves behind a slow frame.
"use strict";

const $ = (id) => document.getElementById(id);
const canvas = $("view");
const ctx = canvas.getContext("2d");

// What the page knows; also read by the browser tests.
const viewer = {
  frames: 0,          // frames drawn
  header: null,       // the last frame's header
  state: null,        // the last state message
  generation: 0,      // the state generation the page has heard of
  errors: [],         // error messages received
  latencyMs: null,    // last time from a move to a frame showing it
};
window.prismViewer = viewer;

let socket = null;
const pending = { orbit: [0, 0], pan: [0, 0], zoom: 0, any: false };
let inFlight = null; // { generation, sent }: a move the server has not yet shown
const fpsTimes = [];

function connect() {
  socket = new WebSocket(`${location.protocol === "https:" ? "wss" : "ws"}://${location.host}/ws`);
  socket.binaryType = "arraybuffer";
  socket.onopen = () => status("connected");
  socket.onclose = () => {
    status("disconnected; reconnecting…");
    setTimeout(connect, 1000);
  };
  socket.onmessage = (event) => {
    if (typeof event.data === "string") {
      text(JSON.parse(event.data));
    } else {
      binary(event.data);
    }
  };
}

function status(s) { $("status").textContent = s; }

function send(message) {
  if (socket && socket.readyState === WebSocket.OPEN) socket.send(JSON.stringify(message));
}

function text(m) {
  if (m.type === "hello") {
    $("scene").textContent = m.scene;
    buildControls(m.controls);
  } else if (m.type === "state") {
    viewer.state = m;
    viewer.generation = Math.max(viewer.generation, m.generation);
    for (const [name, value] of Object.entries(m.values)) {
      const input = document.querySelector(`[name="${name}"]`);
      if (input && document.activeElement !== input) input.value = value;
    }
  } else if (m.type === "error") {
    viewer.errors.push(m.message);
    $("error").textContent = m.message;
  }
}

function binary(buffer) {
  const length = new DataView(buffer).getUint32(0, true);
  const header = JSON.parse(new TextDecoder().decode(new Uint8Array(buffer, 4, length)));
  const payload = 4 + length;
  if (header.kind === "frame") {
    draw(header, new Uint8ClampedArray(buffer, payload));
  } else if (header.kind === "png") {
    download(header.name, buffer.slice(payload));
  }
}

// A preview is smaller than the picture: drawn through a scratch canvas, scaled up smoothly.
const scratch = document.createElement("canvas");
function draw(header, pixels) {
  const [width, height] = header.display;
  if (canvas.width !== width || canvas.height !== height) {
    canvas.width = width;
    canvas.height = height;
  }
  const image = new ImageData(pixels, header.width, header.height);
  if (header.width === width && header.height === height) {
    ctx.putImageData(image, 0, 0);
  } else {
    scratch.width = header.width;
    scratch.height = header.height;
    scratch.getContext("2d").putImageData(image, 0, 0);
    ctx.imageSmoothingEnabled = true;
    ctx.drawImage(scratch, 0, 0, width, height);
  }
  viewer.frames += 1;
  viewer.header = header;
  const now = performance.now();
  fpsTimes.push(now);
  while (fpsTimes.length > 0 && now - fpsTimes[0] > 1000) fpsTimes.shift();
  $("spp").textContent = header.spp;
  $("fps").textContent = fpsTimes.length > 1 ? fpsTimes.length : "–";
  $("frame-ms").textContent = header.frame_ms.toFixed(1);
  $("rays").textContent = (header.rays_per_s / 1e6).toFixed(1);
  status(header.converged ? "converged" : header.preview ? "preview" : "rendering");
  if (inFlight && header.generation > inFlight.generation) {
    viewer.latencyMs = now - inFlight.sent;
    $("latency").textContent = viewer.latencyMs.toFixed(0);
    inFlight = null;
    flush();
  }
}

function download(name, bytes) {
  const url = URL.createObjectURL(new Blob([bytes], { type: "image/png" }));
  const a = document.createElement("a");
  a.href = url;
  a.download = name;
  document.body.appendChild(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}

function buildControls(list) {
  const form = $("controls");
  form.replaceChildren();
  for (const c of list) {
    const label = document.createElement("label");
    label.textContent = c.label;
    let input;
    if (c.kind === "choice") {
      input = document.createElement("select");
      for (const choice of c.choices) input.add(new Option(choice, choice));
    } else {
      input = document.createElement("input");
      if (c.kind === "number") {
        input.type = "number";
        input.min = c.min;
        input.max = c.max;
      } else {
        input.type = "text";
        const list = document.createElement("datalist");
        list.id = `choices-${c.name}`;
        for (const choice of c.choices) list.appendChild(new Option(choice));
        label.appendChild(list);
        input.setAttribute("list", list.id);
      }
    }
    input.name = c.name;
    input.addEventListener("change", () => {
      $("error").textContent = "";
      send({ type: "set", control: c.name, value: String(input.value) });
    });
    label.appendChild(input);
    form.appendChild(label);
  }
  form.addEventListener("submit", (e) => e.preventDefault());
  if (viewer.state) text(viewer.state);
}

// Camera moves: summed while one is in flight; sent at once otherwise, or after 250 ms
// when a frame never came (a move the server refused, or one that changed nothing).
function move(orbit, pan, zoom) {
  pending.orbit[0] += orbit[0];
  pending.orbit[1] += orbit[1];
  pending.pan[0] += pan[0];
  pending.pan[1] += pan[1];
  pending.zoom += zoom;
  pending.any = true;
  flush();
}

function flush() {
  const now = performance.now();
  if (!pending.any || (inFlight && now - inFlight.sent < 250)) return;
  send({ type: "move", orbit: pending.orbit.slice(), pan: pending.pan.slice(), zoom: pending.zoom });
  inFlight = { generation: viewer.generation, sent: now };
  pending.orbit = [0, 0];
  pending.pan = [0, 0];
  pending.zoom = 0;
  pending.any = false;
}
setInterval(flush, 50);

let drag = null;
canvas.addEventListener("pointerdown", (e) => {
  canvas.focus();
  canvas.setPointerCapture(e.pointerId);
  drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button !== 0 };
  canvas.classList.add("dragging");
  e.preventDefault();
});
canvas.addEventListener("pointermove", (e) => {
  if (!drag) return;
  const dx = e.clientX - drag.x;
  const dy = e.clientY - drag.y;
  drag.x = e.clientX;
  drag.y = e.clientY;
  // The picture's height on screen: the canvas box is taller where the picture is
  // letterboxed (object-fit: contain).
  const h = Math.min(canvas.clientHeight, (canvas.clientWidth * canvas.height) / canvas.width) ||
    canvas.height;
  if (drag.pan) {
    // The scene follows the mouse: the camera moves the other way.
    move([0, 0], [-dx / h, dy / h], 0);
  } else {
    // Half a turn across the picture's height.
    move([(dx / h) * 180, (dy / h) * 180], [0, 0], 0);
  }
});
const endDrag = () => {
  drag = null;
  canvas.classList.remove("dragging");
};
canvas.addEventListener("pointerup", endDrag);
canvas.addEventListener("pointercancel", endDrag);
canvas.addEventListener("contextmenu", (e) => e.preventDefault());
canvas.addEventListener("wheel", (e) => {
  e.preventDefault();
  const lines = e.deltaMode === 1 ? e.deltaY * 33 : e.deltaY;
  move([0, 0], [0, 0], -lines / 500);
}, { passive: false });

canvas.addEventListener("keydown", (e) => {
  const step = { ArrowLeft: [-1, 0], a: [-1, 0], ArrowRight: [1, 0], d: [1, 0],
    ArrowUp: [0, 1], w: [0, 1], ArrowDown: [0, -1], s: [0, -1] }[e.key.length === 1 ? e.key.toLowerCase() : e.key];
  if (step) {
    if (e.shiftKey) move([0, 0], [step[0] * 0.05, step[1] * 0.05], 0);
    else move([step[0] * 5, step[1] * 5], [0, 0], 0);
  } else if (e.key === "+" || e.key === "=") {
    move([0, 0], [0, 0], 0.25);
  } else if (e.key === "-" || e.key === "_") {
    move([0, 0], [0, 0], -0.25);
  } else if (e.key === "r" || e.key === "R") {
    send({ type: "reset_camera" });
  } else {
    return;
  }
  e.preventDefault();
});

$("save").addEventListener("click", () => send({ type: "save" }));
$("reset").addEventListener("click", () => send({ type: "reset_camera" }));
connect();
