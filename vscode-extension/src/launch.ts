// How the language server is launched, and what it is told. No `vscode` import:
// everything here is plain data and is unit-tested without VS Code.

import * as fs from "fs";
import * as os from "os";
import * as path from "path";

export const SERVER_MODULE = "osc2lsp";
export const DEFAULT_SERVER_COMMAND = [SERVER_MODULE];
export const INSTALL_HINT = "pip install osc2-toolkit";

export interface ServerSettings {
  /** `osc2.server.command`: program and arguments. */
  command: readonly string[];
  /** `osc2.server.pythonPath`: when non-empty, run `<python> -m osc2lsp`. */
  pythonPath: string;
}

export interface LaunchSpec {
  command: string;
  args: string[];
  /** true when the command is a Python interpreter from `osc2.server.pythonPath`. */
  viaPython: boolean;
}

/**
 * The options the server receives (initializationOptions, didChangeConfiguration
 * and the answer to workspace/configuration). `strict` is null when the user has
 * not set `osc2.strict`: the project's own osc2check configuration decides then.
 */
export interface ServerOptionsPayload {
  strict: boolean | null;
  inlayHints: { enabled: boolean };
}

/** Replace `${workspaceFolder}`, `${userHome}` and a leading `~`. */
export function substituteVariables(value: string, workspaceFolder: string | undefined): string {
  let out = value.replace(/\$\{userHome\}/g, os.homedir());
  if (workspaceFolder !== undefined) out = out.replace(/\$\{workspaceFolder\}/g, workspaceFolder);
  if (out === "~" || out.startsWith("~/") || out.startsWith("~\\")) out = os.homedir() + out.slice(1);
  return out;
}

/** Turn the settings into the command line that starts the server. */
export function launchSpec(settings: ServerSettings, workspaceFolder?: string): LaunchSpec {
  const python = settings.pythonPath.trim();
  if (python !== "") {
    return { command: substituteVariables(python, workspaceFolder), args: ["-m", SERVER_MODULE], viaPython: true };
  }
  const parts = settings.command.filter((p) => typeof p === "string" && p.trim() !== "");
  const [command, ...args] = parts.length > 0 ? parts : DEFAULT_SERVER_COMMAND;
  return {
    command: substituteVariables(command, workspaceFolder),
    args: args.map((a) => substituteVariables(a, workspaceFolder)),
    viaPython: false,
  };
}

export function describe(spec: LaunchSpec): string {
  return [spec.command, ...spec.args].join(" ");
}

/**
 * Find an executable the way a shell would: a name containing a path separator
 * is taken relative to `cwd`; a bare name is searched on PATH (with PATHEXT on
 * Windows). Returns the absolute path, or undefined when there is none.
 */
export function findExecutable(
  command: string,
  cwd: string | undefined,
  env: NodeJS.ProcessEnv = process.env,
  platform: NodeJS.Platform = process.platform,
): string | undefined {
  const windows = platform === "win32";
  const extensions = windows
    ? ["", ...(env.PATHEXT ?? ".COM;.EXE;.BAT;.CMD").split(";").filter((e) => e !== "")]
    : [""];
  const candidates = (base: string) => extensions.map((ext) => base + ext);
  const hasSeparator = command.includes("/") || (windows && command.includes("\\"));
  if (path.isAbsolute(command) || hasSeparator) {
    const base = path.resolve(cwd ?? process.cwd(), command);
    return candidates(base).find((c) => isExecutableFile(c, windows));
  }
  const pathVar = env.PATH ?? env.Path ?? "";
  for (const dir of pathVar.split(path.delimiter)) {
    if (dir === "") continue;
    const found = candidates(path.join(dir, command)).find((c) => isExecutableFile(c, windows));
    if (found) return found;
  }
  return undefined;
}

function isExecutableFile(file: string, windows: boolean): boolean {
  try {
    if (!fs.statSync(file).isFile()) return false;
    if (!windows) fs.accessSync(file, fs.constants.X_OK);
    return true;
  } catch {
    return false;
  }
}

export function optionsPayload(strict: boolean | null, inlayHintsEnabled: boolean): ServerOptionsPayload {
  return { strict, inlayHints: { enabled: inlayHintsEnabled } };
}

/** Parameters of workspace/didChangeConfiguration: the options under the `osc2` section. */
export function didChangeConfigurationParams(payload: ServerOptionsPayload): { settings: { osc2: ServerOptionsPayload } } {
  return { settings: { osc2: payload } };
}

/** What `WorkspaceConfiguration.inspect` reports for one setting. */
export interface InspectedSetting<T> {
  defaultValue?: T;
  globalValue?: T;
  workspaceValue?: T;
  workspaceFolderValue?: T;
}

/**
 * Which settings a value of `osc2.server.*` came from, for the log and the
 * error messages. These are machine settings (`machine-overridable`): in a
 * remote window VS Code reads the user-level value from the Remote settings
 * only, never from the local User settings; folder and workspace settings
 * override both.
 */
export function settingOrigin<T>(inspected: InspectedSetting<T> | undefined, remoteName: string | undefined): string {
  if (inspected?.workspaceFolderValue !== undefined) return "folder settings";
  if (inspected?.workspaceValue !== undefined) return "workspace settings";
  if (inspected?.globalValue !== undefined) return remoteName ? `Remote settings (${remoteName})` : "User settings";
  return "the default";
}

/** The advice a start failure ends with in a remote window (`vscode.env.remoteName`). */
export function remoteHint(remoteName: string | undefined): string {
  if (!remoteName) return "";
  return (
    ` This is a remote window (${remoteName}): \`osc2.server.command\` and \`osc2.server.pythonPath\` are read ` +
    `from the Remote settings or the workspace's settings here, not from your local User settings.`
  );
}

export type StartFailure =
  | { kind: "not-found" }
  | { kind: "spawn-failed"; detail: string }
  | { kind: "exited-during-startup"; lastError?: string | undefined };

/** The message shown when the server cannot be started; it always says how to fix it. */
export function startFailureMessage(spec: LaunchSpec, failure: StartFailure, remoteName?: string): string {
  return describeFailure(spec, failure) + (failure.kind === "exited-during-startup" ? "" : remoteHint(remoteName));
}

function describeFailure(spec: LaunchSpec, failure: StartFailure): string {
  const fix = spec.viaPython
    ? `Install the server into that interpreter (\`${spec.command} -m ${INSTALL_HINT}\`) or point \`osc2.server.pythonPath\` at one that has it.`
    : `Install it with \`${INSTALL_HINT}\`, or set \`osc2.server.pythonPath\` to a Python interpreter that has it.`;
  switch (failure.kind) {
    case "not-found":
      return spec.viaPython
        ? `OSC2: the Python interpreter \`${spec.command}\` (setting \`osc2.server.pythonPath\`) was not found. ` +
            `Point \`osc2.server.pythonPath\` at a Python that has the toolkit (\`${INSTALL_HINT}\`), or clear it to use \`osc2.server.command\`.`
        : `OSC2: the language server command \`${spec.command}\` was not found. ${fix}`;
    case "spawn-failed":
      return `OSC2: could not start the language server (\`${describe(spec)}\`): ${failure.detail}. ${fix}`;
    case "exited-during-startup": {
      const said = failure.lastError ? ` (it said: ${failure.lastError})` : "";
      return `OSC2: the language server (\`${describe(spec)}\`) exited during start-up${said}. ${fix} Its full output is in "OSC2 Language Server".`;
    }
  }
}
