import assert = require("node:assert/strict");
import * as fs from "fs";
import * as os from "os";
import * as path from "path";
import { describe, it } from "node:test";
import {
  didChangeConfigurationParams,
  findExecutable,
  launchSpec,
  optionsPayload,
  remoteHint,
  settingOrigin,
  startFailureMessage,
  substituteVariables,
} from "../../src/launch";

describe("launchSpec", () => {
  it("uses osc2.server.command as program and arguments", () => {
    assert.deepEqual(launchSpec({ command: ["osc2lsp", "--log", "debug"], pythonPath: "" }), {
      command: "osc2lsp",
      args: ["--log", "debug"],
      viaPython: false,
    });
  });

  it("falls back to osc2lsp for an empty command", () => {
    assert.deepEqual(launchSpec({ command: [], pythonPath: "  " }).command, "osc2lsp");
    assert.deepEqual(launchSpec({ command: ["", " "], pythonPath: "" }).command, "osc2lsp");
  });

  it("runs `<python> -m osc2lsp` when a python path is set", () => {
    assert.deepEqual(launchSpec({ command: ["osc2lsp"], pythonPath: "/venv/bin/python" }), {
      command: "/venv/bin/python",
      args: ["-m", "osc2lsp"],
      viaPython: true,
    });
  });

  it("substitutes ${workspaceFolder}, ${userHome} and ~", () => {
    const spec = launchSpec({ command: [], pythonPath: "${workspaceFolder}/.venv/bin/python" }, "/ws");
    assert.equal(spec.command, "/ws/.venv/bin/python");
    assert.equal(substituteVariables("~/x", undefined), path.join(os.homedir(), "x"));
    assert.equal(substituteVariables("${userHome}/y", undefined), `${os.homedir()}/y`);
    assert.equal(substituteVariables("${workspaceFolder}/z", undefined), "${workspaceFolder}/z");
  });
});

describe("findExecutable", () => {
  const dir = fs.mkdtempSync(path.join(os.tmpdir(), "osc2-find-"));
  const exe = path.join(dir, "osc2lsp");
  fs.writeFileSync(exe, "#!/bin/sh\n", { mode: 0o755 });
  const plain = path.join(dir, "not-executable");
  fs.writeFileSync(plain, "", { mode: 0o644 });

  it("searches PATH for a bare name", () => {
    assert.equal(findExecutable("osc2lsp", undefined, { PATH: ["/nowhere", dir].join(path.delimiter) }, "linux"), exe);
    assert.equal(findExecutable("osc2lsp", undefined, { PATH: "/nowhere" }, "linux"), undefined);
  });

  it("resolves a path relative to the working directory", () => {
    assert.equal(findExecutable("./osc2lsp", dir, {}, "linux"), exe);
    assert.equal(findExecutable(exe, undefined, {}, "linux"), exe);
  });

  it("skips files that are not executable", { skip: process.platform === "win32" }, () => {
    assert.equal(findExecutable(plain, undefined, {}, "linux"), undefined);
  });

  it("tries PATHEXT on Windows", () => {
    const winDir = fs.mkdtempSync(path.join(os.tmpdir(), "osc2-find-win-"));
    fs.writeFileSync(path.join(winDir, "osc2lsp.EXE"), "");
    assert.equal(
      findExecutable("osc2lsp", undefined, { PATH: winDir, PATHEXT: ".COM;.EXE" }, "win32"),
      path.join(winDir, "osc2lsp.EXE"),
    );
  });
});

describe("options sent to the server", () => {
  it("has the same shape in initializationOptions and didChangeConfiguration", () => {
    const payload = optionsPayload(true, false);
    assert.deepEqual(payload, { strict: true, inlayHints: { enabled: false } });
    assert.deepEqual(optionsPayload(null, true), { strict: null, inlayHints: { enabled: true } });
    assert.deepEqual(didChangeConfigurationParams(payload), { settings: { osc2: payload } });
  });
});

describe("startFailureMessage", () => {
  const command = launchSpec({ command: ["osc2lsp"], pythonPath: "" });
  const python = launchSpec({ command: [], pythonPath: "/usr/bin/python3" });

  it("always says how to fix it", () => {
    for (const spec of [command, python]) {
      for (const failure of [
        { kind: "not-found" } as const,
        { kind: "spawn-failed", detail: "EACCES" } as const,
        { kind: "exited-during-startup", lastError: "No module named osc2lsp" } as const,
      ]) {
        const text = startFailureMessage(spec, failure);
        assert.match(text, /pip install osc2-toolkit/, text);
        assert.match(text, /osc2\.server\.pythonPath/, text);
      }
    }
  });

  it("quotes what the server said", () => {
    assert.match(
      startFailureMessage(python, { kind: "exited-during-startup", lastError: "No module named osc2lsp" }),
      /\/usr\/bin\/python3 -m osc2lsp.*No module named osc2lsp.*\/usr\/bin\/python3 -m pip install osc2-toolkit/,
    );
  });
});

describe("settings of the server in remote windows", () => {
  it("names the settings a value came from; a user-level value is the Remote settings' in a remote window", () => {
    assert.equal(settingOrigin({ defaultValue: 1, workspaceFolderValue: 2, workspaceValue: 3 }, undefined), "folder settings");
    assert.equal(settingOrigin({ workspaceValue: 3, globalValue: 4 }, "wsl"), "workspace settings");
    assert.equal(settingOrigin({ globalValue: 4 }, undefined), "User settings");
    assert.equal(settingOrigin({ globalValue: 4 }, "ssh-remote"), "Remote settings (ssh-remote)");
    assert.equal(settingOrigin({ defaultValue: 1 }, "ssh-remote"), "the default");
    assert.equal(settingOrigin(undefined, undefined), "the default");
  });

  it("tells a remote window's user where to set the server", () => {
    const spec = launchSpec({ command: ["osc2lsp"], pythonPath: "" });
    assert.equal(remoteHint(undefined), "");
    const remote = startFailureMessage(spec, { kind: "not-found" }, "ssh-remote");
    assert.ok(remote.startsWith(startFailureMessage(spec, { kind: "not-found" })));
    assert.match(remote, /remote window \(ssh-remote\).*Remote settings or the workspace's settings/);
    assert.doesNotMatch(startFailureMessage(spec, { kind: "exited-during-startup" }, "wsl"), /remote window/);
  });
});
