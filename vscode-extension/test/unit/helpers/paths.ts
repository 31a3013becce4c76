// Locations used by the tests, found from wherever the compiled test runs.

import * as fs from "fs";
import * as path from "path";

/** The extension's folder (the one whose package.json is named "osc2"). */
export function extensionRoot(): string {
  let dir = __dirname;
  for (;;) {
    const manifest = path.join(dir, "package.json");
    if (fs.existsSync(manifest) && JSON.parse(fs.readFileSync(manifest, "utf8")).name === "osc2") return dir;
    const parent = path.dirname(dir);
    if (parent === dir) throw new Error(`no osc2 package.json above ${__dirname}`);
    dir = parent;
  }
}

export function fromRoot(...parts: string[]): string {
  return path.join(extensionRoot(), ...parts);
}

/** Poll until `condition` holds, or fail after `timeoutMs`. */
export async function waitFor(what: string, condition: () => boolean, timeoutMs = 15000): Promise<void> {
  const start = Date.now();
  while (!condition()) {
    if (Date.now() - start > timeoutMs) throw new Error(`timed out waiting for ${what}`);
    await new Promise((resolve) => setTimeout(resolve, 25));
  }
}
