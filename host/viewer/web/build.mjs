// Builds the viewer's page: bundles src/main.js and everything it imports (three.js from
// node_modules) into one minified script, writes index.html with that script and its
// style inlined, and writes the Content-Security-Policy that allows exactly them (by their
// SHA-256) and nothing else: no other script, no eval, no request but to the viewer.
// Run by CMake (cmake/viewer_page.cmake):
//   node build.mjs NODE_MODULES OUTPUT.html OUTPUT-POLICY.txt
import { createHash } from "node:crypto";
import { readFileSync, writeFileSync } from "node:fs";
import { createRequire } from "node:module";
import path from "node:path";
import { fileURLToPath } from "node:url";

const [modules, outputPage, outputPolicy] = process.argv.slice(2).map(p => path.resolve(p));
if (!outputPolicy) {
  console.error("usage: node build.mjs NODE_MODULES OUTPUT.html OUTPUT-POLICY.txt");
  process.exit(2);
}
const here = path.dirname(fileURLToPath(import.meta.url));
// esbuild is installed in the build folder, not beside this file.
const esbuild = createRequire(path.join(modules, "package.json"))("esbuild");

const bundle = await esbuild.build({
  entryPoints: [path.join(here, "src", "main.js")],
  bundle: true,
  minify: true,
  format: "iife",
  target: "es2020",
  charset: "utf8",
  legalComments: "eof",  // three.js's MIT notice stays in the page
  nodePaths: [modules],
  write: false,
  logLevel: "warning",
});
const script = bundle.outputFiles[0].text;

// The template's <style> element and its placeholder for the script.
const template = readFileSync(path.join(here, "index.html"), "utf8");
const style = template.match(/<style>([\s\S]*?)<\/style>/);
const placeholder = "<!-- the bundled script -->";
if (!style || !template.includes(placeholder)) throw new Error("index.html needs one <style> and " + placeholder);
// An inline script ends at the first "</script" whatever quotes it stands in.
if (/<\/script/i.test(script)) throw new Error("the bundle holds '</script', which would end the inline script");
const page = template.replace(placeholder, () => `<script>${script}</script>`);

const sha256 = text => `'sha256-${createHash("sha256").update(text, "utf8").digest("base64")}'`;
const policy = [
  "default-src 'none'",
  `script-src ${sha256(script)}`,
  `style-src ${sha256(style[1])}`,
  "connect-src 'self'",        // the viewer's routes and its event stream
  "img-src 'self' data: blob:", // "save image" makes a data URL of the canvas
  "base-uri 'none'",
  "form-action 'none'",
  "frame-ancestors 'none'",
].join("; ");
writeFileSync(outputPage, page);
writeFileSync(outputPolicy, policy + "\n");
