// The toolkit's command-line tools (osc2run, osc2check) as used by the
// extension's commands. No `vscode` import: unit-tested without VS Code.

import * as fs from "fs";
import * as path from "path";
import { INSTALL_HINT } from "./launch";

export type Tool = "osc2run" | "osc2check";

/**
 * The program to run for a tool. With `osc2.server.pythonPath` set, a script
 * installed next to that interpreter (a virtual environment's bin/ or
 * Scripts/) wins over PATH; otherwise the bare name is used.
 */
export function toolCommand(
  tool: Tool,
  pythonPath: string | undefined,
  platform: NodeJS.Platform = process.platform,
  exists: (file: string) => boolean = isFile,
): string {
  const python = pythonPath?.trim();
  if (python) {
    const dir = path.dirname(python);
    const names = platform === "win32" ? [`${tool}.exe`, path.join("Scripts", `${tool}.exe`)] : [tool];
    for (const name of names) {
      const candidate = path.join(dir, name);
      if (exists(candidate)) return candidate;
    }
  }
  return tool;
}

function isFile(file: string): boolean {
  try {
    return fs.statSync(file).isFile();
  } catch {
    return false;
  }
}

type ShellKind = "posix" | "powershell" | "cmd";

export function shellKind(shell: string | undefined, platform: NodeJS.Platform = process.platform): ShellKind {
  const name = path.basename((shell ?? "").replace(/\\/g, "/")).toLowerCase();
  if (/^cmd(\.exe)?$/.test(name)) return "cmd";
  if (/^(pwsh|powershell)(\.exe)?$/.test(name)) return "powershell";
  if (name === "") return platform === "win32" ? "powershell" : "posix";
  return "posix";
}

/** A command line for an interactive terminal running `shell`, every argument quoted as that shell needs. */
export function shellCommandLine(argv: readonly string[], shell: string | undefined, platform: NodeJS.Platform = process.platform): string {
  const kind = shellKind(shell, platform);
  switch (kind) {
    case "posix":
      return argv.map((a) => (/^[\w@%+=:,./-]+$/.test(a) ? a : `'${a.replace(/'/g, `'\\''`)}'`)).join(" ");
    case "cmd":
      return argv.map((a) => (/^[\w@%+=:,./\\-]+$/.test(a) ? a : `"${a.replace(/"/g, '""')}"`)).join(" ");
    case "powershell": {
      const quoted = argv.map((a) => (/^[\w@+=:,./\\-]+$/.test(a) ? a : `'${a.replace(/'/g, "''")}'`));
      // A quoted program name needs the call operator in PowerShell.
      return quoted[0]?.startsWith("'") ? `& ${quoted.join(" ")}` : quoted.join(" ");
    }
  }
}

/** The arguments of `osc2check` for the "Show witness" command. */
export function witnessArgs(file: string): string[] {
  return ["--witness", file, "--output-format", "json"];
}

export interface ProcessResult {
  exitCode: number | null;
  stdout: string;
  stderr: string;
  /** set when the process could not be run or was killed (ENOENT, timeout, buffer overflow) */
  spawnError?: { code?: string | number; message: string };
}

export type CheckerOutcome =
  | { kind: "json"; text: string; exitCode: number | null }
  | { kind: "not-found" }
  | { kind: "failed"; summary: string; exitCode: number | null };

/**
 * What `osc2check --witness … --output-format json` produced. Only JSON that
 * the checker actually printed is shown; anything else is reported as a
 * failure carrying the checker's own last error line.
 */
export function interpretChecker(result: ProcessResult): CheckerOutcome {
  if (result.spawnError?.code === "ENOENT") return { kind: "not-found" };
  const stdout = result.stdout.trim();
  if (stdout !== "" && !result.spawnError) {
    try {
      return { kind: "json", text: JSON.stringify(JSON.parse(stdout), null, 2) + "\n", exitCode: result.exitCode };
    } catch {
      // not JSON: fall through and report it
    }
  }
  const lastLine = (text: string) =>
    text
      .split(/\r?\n/)
      .map((l) => l.trim())
      .filter((l) => l !== "")
      .pop();
  const summary =
    result.spawnError?.message ?? lastLine(result.stderr) ?? lastLine(result.stdout) ?? "the checker printed nothing";
  return { kind: "failed", summary, exitCode: result.exitCode };
}

export function checkerNotFoundMessage(command: string): string {
  return `OSC2: \`${command}\` was not found. Install the toolkit with \`${INSTALL_HINT}\`, or set \`osc2.server.pythonPath\` to a Python interpreter whose environment has it.`;
}

export function checkerFailedMessage(outcome: { summary: string; exitCode: number | null }): string {
  const code = outcome.exitCode === null ? "" : ` (exit code ${outcome.exitCode})`;
  return `OSC2: osc2check --witness failed${code}: ${outcome.summary}`;
}
