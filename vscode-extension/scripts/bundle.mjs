// Bundle the client (src/extension.ts + vscode-languageclient) into dist/extension.js.
//   node scripts/bundle.mjs           minified bundle for packaging
//   node scripts/bundle.mjs --dev     with an inline source map, not minified

import * as esbuild from "esbuild";
import { dirname, join } from "node:path";
import { fileURLToPath } from "node:url";

const root = join(dirname(fileURLToPath(import.meta.url)), "..");
const dev = process.argv.includes("--dev");

await esbuild.build({
  entryPoints: [join(root, "src", "extension.ts")],
  outfile: join(root, "dist", "extension.js"),
  bundle: true,
  platform: "node",
  format: "cjs",
  target: "node18",
  external: ["vscode"],
  minify: !dev,
  sourcemap: dev ? "inline" : false,
  legalComments: "none",
  logLevel: "warning",
});
console.log(`bundled dist/extension.js${dev ? " (dev)" : ""}`);
