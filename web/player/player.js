// Plays an eulersplat loop forever (es_export --web): the splats of loop
// frame 0 come from the loop file's PLY, and every frame rewrites the water
// splats' position, color and opacity from its per-frame table (format in
// core/loop/loop_file.h). Drag to orbit, scroll to zoom, space to pause.
//
// URL parameters: frame=K shows loop frame K, paused; camera=I starts from
// the scene's camera I at its image size. window.esLoop lets a test drive
// the same controls.
import * as THREE from "three";
import { OrbitControls } from "three/addons/controls/OrbitControls.js";
import { PackedSplats, SparkRenderer, SplatMesh } from "@sparkjsdev/spark";

const kMagic = "ESLOOP1\0";
const kValuesPerSplat = 7;

function parseLoop(buffer) {
  const bytes = new Uint8Array(buffer);
  const view = new DataView(buffer);
  const magic = String.fromCharCode(...bytes.subarray(0, 8));
  if (magic !== kMagic) throw new Error("not an eulersplat loop file");
  const u32 = (offset) => view.getUint32(offset, true);
  const f32 = (offset) => view.getFloat32(offset, true);
  const loop = {
    numSplats: u32(12),
    numWater: u32(16),
    numFrames: u32(20),
    fps: f32(24),
    background: [f32(28), f32(32), f32(36)],
  };
  const plyOffset = u32(40), plyBytes = u32(44);
  loop.ply = bytes.slice(plyOffset, plyOffset + plyBytes);
  const tableOffset = Math.ceil((plyOffset + plyBytes) / 4) * 4;
  loop.table = new Uint16Array(
      buffer, tableOffset, loop.numFrames * loop.numWater * kValuesPerSplat);
  return loop;
}

function halfToFloat(h) {
  const exponent = (h >> 10) & 31, mantissa = h & 1023;
  const sign = h & 32768 ? -1 : 1;
  if (exponent === 0) return sign * mantissa * 2 ** -24;
  if (exponent === 31) return mantissa ? NaN : sign * Infinity;
  return sign * (1 + mantissa / 1024) * 2 ** (exponent - 15);
}

// The packed words of the water splats (the first numWater) at every frame,
// encoded once by Spark itself so that playing a frame is one copy.
function encodeFrames(packed, loop) {
  const w = loop.numWater;
  const scales = [], quats = [];
  for (let k = 0; k < w; ++k) {
    const s = packed.getSplat(k);
    scales.push(s.scales.clone());
    quats.push(s.quaternion.clone());
  }
  const center = new THREE.Vector3(), color = new THREE.Color();
  const frames = [];
  for (let f = 0; f < loop.numFrames; ++f) {
    let v = f * w * kValuesPerSplat;
    for (let k = 0; k < w; ++k, v += kValuesPerSplat) {
      const h = (i) => halfToFloat(loop.table[v + i]);
      center.set(h(0), h(1), h(2));
      color.setRGB(h(3), h(4), h(5));
      packed.setSplat(k, center, scales[k], quats[k], h(6), color);
    }
    frames.push(packed.packedArray.slice(0, 4 * w));
  }
  return frames;
}

// A three.js camera placed and projecting as a COLMAP camera (world-to-
// camera rotation, x right, y down, z forward; pinhole intrinsics).
function applyColmapCamera(camera, c) {
  const r = c.rotation;  // row-major world-to-camera
  const rt = new THREE.Matrix4().set(
      r[0], -r[3], -r[6], 0,
      r[1], -r[4], -r[7], 0,
      r[2], -r[5], -r[8], 0,
      0, 0, 0, 1);  // camera-to-world, y and z flipped to three's axes
  const t = c.translation;
  camera.position.set(
      -(r[0] * t[0] + r[3] * t[1] + r[6] * t[2]),
      -(r[1] * t[0] + r[4] * t[1] + r[7] * t[2]),
      -(r[2] * t[0] + r[5] * t[1] + r[8] * t[2]));
  camera.quaternion.setFromRotationMatrix(rt);
  camera.up.set(-r[3], -r[4], -r[5]);
  setIntrinsics(camera, c);
}

function setIntrinsics(camera, c) {
  const n = camera.near, f = camera.far, w = c.width, h = c.height;
  camera.intrinsics = c;
  camera.projectionMatrix.set(
      2 * c.fx / w, 0, 1 - 2 * c.cx / w, 0,
      0, 2 * c.fy / h, 2 * c.cy / h - 1, 0,
      0, 0, -(f + n) / (f - n), -2 * f * n / (f - n),
      0, 0, -1, 0);
  camera.projectionMatrixInverse.copy(camera.projectionMatrix).invert();
}

// Keeps the camera's intrinsics when the window is resized: the focal
// length scales with the height, the principal point stays centered.
function fitToWindow(camera, renderer, base) {
  const w = window.innerWidth, h = window.innerHeight;
  renderer.setSize(w, h);
  const s = h / base.height;
  setIntrinsics(camera, {
    width: w, height: h, fx: base.fx * s, fy: base.fy * s,
    cx: w / 2, cy: h / 2,
  });
}

async function main() {
  const info = document.getElementById("info");
  const params = new URLSearchParams(location.search);
  const meta = await (await fetch("view.json")).json();
  const loop = parseLoop(await (await fetch(meta.loop)).arrayBuffer());

  // camera=I renders exactly that camera's image; otherwise fill the window.
  const fixedSize = params.has("camera");
  const renderer = new THREE.WebGLRenderer({ preserveDrawingBuffer: true });
  renderer.setPixelRatio(fixedSize ? 1 : Math.min(window.devicePixelRatio, 2));
  renderer.setClearColor(new THREE.Color(...loop.background), 1);
  document.body.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  const spark = new SparkRenderer({ renderer });
  scene.add(spark);
  const packed = new PackedSplats({ fileBytes: loop.ply, fileType: "ply" });
  await packed.initialized;
  if (packed.numSplats !== loop.numSplats) {
    throw new Error(`PLY holds ${packed.numSplats} splats, header says ` +
                    `${loop.numSplats}`);
  }
  const frames = encodeFrames(packed, loop);
  const mesh = new SplatMesh({ packedSplats: packed });
  await mesh.initialized;
  scene.add(mesh);

  const camera = new THREE.PerspectiveCamera(50, 1, 0.01, 1000);
  const cameraIndex = Number(params.get("camera") ?? 0);
  const start = meta.cameras[cameraIndex] ?? meta.cameras[0];
  applyColmapCamera(camera, start);
  const resize = () => {
    if (fixedSize) {
      renderer.setSize(start.width, start.height);
    } else {
      fitToWindow(camera, renderer, start);
    }
  };
  resize();
  window.addEventListener("resize", resize);
  // Orbit around a point straight ahead (OrbitControls turns the camera
  // towards its target as soon as it is made: place the camera again).
  const forward = new THREE.Vector3(0, 0, -1).applyQuaternion(camera.quaternion);
  const target = camera.position.clone()
      .addScaledVector(forward, meta.target_distance);
  const controls = new OrbitControls(camera, renderer.domElement);
  applyColmapCamera(camera, start);
  resize();
  controls.target.copy(target);
  controls.update();
  const keepProjection = () => setIntrinsics(camera, camera.intrinsics);
  controls.addEventListener("change", keepProjection);

  let shown = -1;
  let paused = params.has("frame");
  let frame = Number(params.get("frame") ?? 0) % loop.numFrames;
  const t0 = performance.now();
  function show(f) {
    if (f === shown) return;
    packed.packedArray.set(frames[f], 0);
    packed.needsUpdate = true;
    mesh.updateVersion();
    shown = f;
  }
  window.addEventListener("keydown", (e) => {
    if (e.code === "Space") paused = !paused;
  });
  renderer.setAnimationLoop(() => {
    if (!paused) {
      frame = Math.floor((performance.now() - t0) / 1000 * loop.fps) %
              loop.numFrames;
    }
    show(frame);
    controls.update();
    keepProjection();
    renderer.render(scene, camera);
    // The page showed es_export's poster until now.
    document.getElementById("poster")?.remove();
    info.textContent = `loop frame ${frame + 1} / ${loop.numFrames}` +
        (paused ? " (paused)" : "") +
        " · drag to orbit, scroll to zoom, space to pause";
  });

  // For tests: show frame f (paused) and return once it is drawn in depth
  // order. Spark sorts in a worker, frames behind the draw, and keeps
  // re-sorting for a while after loading, so neither a fixed wait nor an
  // idle sorter says the frame is sorted: regenerate the splats now, wait
  // for a sort that started after that to finish, then draw twice.
  const nextFrame = () => new Promise((resolve) => requestAnimationFrame(resolve));
  window.esLoop = {
    numFrames: loop.numFrames,
    numWater: loop.numWater,
    async showFrame(f) {
      paused = true;
      frame = f % loop.numFrames;
      while (shown !== frame) await nextFrame();
      const generated = performance.now();
      spark.update({ scene, camera });
      while (spark.lastSortTime < generated) await nextFrame();
      const ours = spark.lastSortTime;
      while (spark.sorting && spark.lastSortTime === ours) await nextFrame();
      await nextFrame();
      await nextFrame();
    },
  };
  window.esLoopReady = true;
}

main().catch((error) => {
  document.getElementById("info").textContent = "error: " + error.message;
  console.error(error);
});
