// Opens an es_export web page in headless Chromium and saves screenshots of
// chosen loop frames, for tests/browser_test.cc. Serves the page from
// 127.0.0.1 (browsers do not run module pages from file://) and fails on
// any console error or uncaught exception.
//
//   node screenshot_loop.mjs --page DIR --out DIR --frames 0,3
//        [--camera 0] [--chromium /usr/bin/chromium] [--timeout_ms 60000]
//        [--window WxH]
//
// Writes OUT/frame_<k>.png per frame and OUT/console.txt (every console
// message); exit status 0 only when the page loaded without errors. The
// screenshots are the canvas alone, at the camera's image size, or with
// --window the whole page as a person sees it in a window of that size.
import { createServer } from "node:http";
import { readFile, writeFile } from "node:fs/promises";
import { extname, join, normalize } from "node:path";
import puppeteer from "puppeteer-core";

function parseArgs(argv) {
  const args = { camera: "0", chromium: "/usr/bin/chromium",
                 timeout_ms: "60000" };
  for (let i = 0; i < argv.length; i += 2) {
    if (!argv[i].startsWith("--") || i + 1 >= argv.length) {
      throw new Error(`bad argument ${argv[i]}`);
    }
    args[argv[i].slice(2)] = argv[i + 1];
  }
  for (const required of ["page", "out", "frames"]) {
    if (!args[required]) throw new Error(`--${required} is required`);
  }
  return args;
}

const kTypes = {
  ".html": "text/html", ".js": "text/javascript", ".json": "application/json",
};

// A static file server for the page folder only.
function serve(root) {
  const server = createServer(async (request, response) => {
    const path = decodeURIComponent(new URL(request.url, "http://x").pathname);
    const file = normalize(join(root, path === "/" ? "index.html" : path));
    if (!file.startsWith(normalize(root))) {
      response.writeHead(403).end();
      return;
    }
    try {
      const body = await readFile(file);
      response.writeHead(200, {
        "Content-Type": kTypes[extname(file)] ?? "application/octet-stream",
      });
      response.end(body);
    } catch {
      response.writeHead(404).end();
    }
  });
  return new Promise((resolve) => {
    server.listen(0, "127.0.0.1", () => resolve(server));
  });
}

const t0 = Date.now();
const stamp = (what) => console.log(`${Date.now() - t0} ms: ${what}`);

async function main() {
  const args = parseArgs(process.argv.slice(2));
  const timeout = Number(args.timeout_ms);
  const server = await serve(args.page);
  const port = server.address().port;
  const browser = await puppeteer.launch({
    executablePath: args.chromium,
    headless: true,
    // WebGL2 without a GPU: Chromium's software rasterizer.
    args: ["--no-sandbox", "--use-angle=swiftshader",
           "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist"],
  });
  stamp("browser started");
  const log = [];
  let errors = 0;
  try {
    const page = await browser.newPage();
    page.on("console", (message) => {
      log.push(`${message.type()}: ${message.text()}`);
      if (message.type() === "error") ++errors;
    });
    page.on("pageerror", (error) => {
      log.push(`pageerror: ${error.message}`);
      ++errors;
    });
    page.on("requestfailed", (request) => {
      log.push(`requestfailed: ${request.url()}`);
      ++errors;
    });
    page.on("response", (response) => {
      if (response.status() >= 400) {
        log.push(`${response.status()}: ${response.url()}`);
      }
    });
    page.on("request", (request) => {
      const url = request.url();
      const local = url.startsWith(`http://127.0.0.1:${port}/`) ||
                    url.startsWith("blob:") || url.startsWith("data:");
      if (!local) {
        log.push(`outside request: ${request.url()}`);
        ++errors;
      }
    });
    let query = `camera=${args.camera}&frame=0`;
    if (args.window) {
      const [width, height] = args.window.split("x").map(Number);
      await page.setViewport({ width, height });
      query = "frame=0";
    } else {
      const view = JSON.parse(await readFile(join(args.page, "view.json")));
      const camera = view.cameras[Number(args.camera)];
      await page.setViewport({ width: camera.width, height: camera.height });
    }
    await page.goto(`http://127.0.0.1:${port}/?${query}`,
                    { timeout, waitUntil: "load" });
    stamp("page loaded");
    await page.waitForFunction("window.esLoopReady === true", { timeout });
    stamp("player ready");
    if (!args.window) {
      // The splats only, without the text over them.
      await page.evaluate(() => {
        document.getElementById("info").style.display = "none";
      });
    }
    const target = args.window ? page : await page.$("canvas");
    for (const frame of args.frames.split(",").map(Number)) {
      await page.evaluate((f) => window.esLoop.showFrame(f), frame);
      await target.screenshot({ path: join(args.out, `frame_${frame}.png`) });
      stamp(`frame ${frame}`);
    }
  } finally {
    await writeFile(join(args.out, "console.txt"), log.join("\n") + "\n");
    await browser.close();
    server.close();
  }
  if (errors > 0) {
    console.error(`${errors} console errors:\n${log.join("\n")}`);
    process.exit(1);
  }
}

main().catch((error) => {
  console.error(error.stack ?? String(error));
  process.exit(2);
});
