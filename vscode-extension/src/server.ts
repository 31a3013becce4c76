// Lifecycle of the osc2lsp language client: start, stop, restart, and telling
// the user how to fix a server that cannot start.

import * as cp from "child_process";
import { Writable } from "stream";
import * as vscode from "vscode";
import {
  CloseAction,
  CloseHandlerResult,
  DidChangeConfigurationNotification,
  ErrorAction,
  ErrorHandlerResult,
  LanguageClient,
  LanguageClientOptions,
  RevealOutputChannelOn,
  ServerOptions,
  State,
  StreamInfo,
} from "vscode-languageclient/node";
import {
  LaunchSpec,
  ServerOptionsPayload,
  ServerSettings,
  StartFailure,
  didChangeConfigurationParams,
  findExecutable,
  launchSpec,
  optionsPayload,
  settingOrigin,
  startFailureMessage,
} from "./launch";

export const CLIENT_ID = "osc2"; // the client reads `osc2.trace.server` because of this id
export const CLIENT_NAME = "OSC2 Language Server";
export const OPEN_SETTINGS = "Open Settings";
export const SHOW_OUTPUT = "Show Output";

const MAX_RESTARTS = 4;
const RESTART_WINDOW_MS = 3 * 60 * 1000;
const EXIT_WAIT_MS = 2000;

const delay = (ms: number) => new Promise((resolve) => setTimeout(resolve, ms));

/** A LanguageClient whose own error pop-ups can be silenced while we report start failures ourselves. */
class Osc2LanguageClient extends LanguageClient {
  quiet = false;
  override error(message: string, data?: unknown, showNotification?: boolean | "force"): void {
    super.error(message, data, this.quiet ? false : showNotification);
  }
  // When the server dies before answering `initialize`, the library calls
  // `void this.stop()` while still "starting", which can only reject (and
  // nobody handles that rejection). There is nothing to stop then: the
  // controller kills the process itself.
  override async stop(timeout?: number): Promise<void> {
    if (this.state === State.Starting) return;
    return super.stop(timeout);
  }
}

export function readOptions(): ServerOptionsPayload {
  const config = vscode.workspace.getConfiguration("osc2");
  const strict = config.inspect<boolean>("strict");
  const explicit = [strict?.workspaceFolderValue, strict?.workspaceValue, strict?.globalValue].some((v) => v !== undefined);
  return optionsPayload(
    explicit ? config.get<boolean>("strict", false) : null,
    config.get<boolean>("inlayHints.enabled", false),
  );
}

/** The `osc2` section as the server should see it: VS Code fills in `strict: false` even when unset. */
function withOptions(section: unknown): unknown {
  if (section === null || typeof section !== "object" || Array.isArray(section)) return section;
  const options = readOptions();
  const inlayHints = (section as { inlayHints?: unknown }).inlayHints;
  return {
    ...section,
    strict: options.strict,
    inlayHints: { ...(typeof inlayHints === "object" && inlayHints !== null ? inlayHints : {}), ...options.inlayHints },
  };
}

function workspaceFolderPath(): string | undefined {
  return vscode.workspace.workspaceFolders?.[0]?.uri.fsPath;
}

/**
 * `osc2.server.command` and `osc2.server.pythonPath`, read for the first workspace
 * folder (so that folder settings apply too), and where each came from.
 */
export function readServerSettings(): { settings: ServerSettings; origins: string[] } {
  const scope = vscode.workspace.workspaceFolders?.[0]?.uri;
  const config = vscode.workspace.getConfiguration("osc2.server", scope);
  const remote = vscode.env.remoteName;
  const settings = {
    command: config.get<string[]>("command", ["osc2lsp"]),
    pythonPath: config.get<string>("pythonPath", ""),
  };
  const origins = [
    `osc2.server.command ${JSON.stringify(settings.command)} from ${settingOrigin(config.inspect("command"), remote)}`,
    `osc2.server.pythonPath ${JSON.stringify(settings.pythonPath)} from ${settingOrigin(config.inspect("pythonPath"), remote)}`,
  ];
  return { settings, origins };
}

/** Open the settings where `osc2.server.*` apply in this window. */
export function openServerSettings(): Thenable<unknown> {
  const command = vscode.env.remoteName ? "workbench.action.openRemoteSettings" : "workbench.action.openSettings";
  return vscode.commands.executeCommand(command, vscode.env.remoteName ? { query: "osc2.server" } : "osc2.server");
}

export class ServerController implements vscode.Disposable {
  private client: Osc2LanguageClient | undefined;
  private process: cp.ChildProcess | undefined;
  private queue: Promise<void> = Promise.resolve();
  private crashes: number[] = [];

  constructor(private readonly output: vscode.OutputChannel) {}

  /** Operations run one after the other, so a restart never races a start. */
  private enqueue(op: () => Promise<void>): Promise<void> {
    this.queue = this.queue.then(op, op);
    return this.queue;
  }

  start(): Promise<void> {
    return this.enqueue(() => this.doStart());
  }

  stop(): Promise<void> {
    return this.enqueue(() => this.doStop());
  }

  restart(): Promise<void> {
    return this.enqueue(async () => {
      await this.doStop();
      await this.doStart();
    });
  }

  get running(): boolean {
    return this.client?.isRunning() ?? false;
  }

  /** Send the current `osc2.strict` / `osc2.inlayHints` to a running server. */
  async notifyOptions(): Promise<void> {
    const client = this.client;
    if (!client || !client.isRunning()) return;
    const params = didChangeConfigurationParams(readOptions());
    this.output.appendLine(`[osc2] workspace/didChangeConfiguration ${JSON.stringify(params.settings)}`);
    await client.sendNotification(DidChangeConfigurationNotification.type, params);
  }

  dispose(): void {
    void this.stop();
  }

  private async doStart(): Promise<void> {
    if (this.client) return;
    const cwd = workspaceFolderPath();
    const { settings, origins } = readServerSettings();
    for (const origin of origins) this.output.appendLine(`[osc2] ${origin}`);
    const spec = launchSpec(settings, cwd);
    const executable = findExecutable(spec.command, cwd);
    if (executable === undefined) {
      this.reportStartFailure(spec, { kind: "not-found" });
      return;
    }
    this.output.appendLine(`[osc2] starting ${[executable, ...spec.args].join(" ")}`);

    // We spawn the process ourselves (rather than handing the client an
    // Executable) to keep its stderr for the error message, and we give the
    // client a writer that drops messages once the process has gone: otherwise
    // a server that dies at start-up makes the client's pending writes fail
    // with unhandled ERR_STREAM_DESTROYED rejections.
    let stderrTail = "";
    let spawned: { child: cp.ChildProcessWithoutNullStreams; closed: Promise<void> } | undefined;
    const serverOptions: ServerOptions = () =>
      new Promise<StreamInfo>((resolve, reject) => {
        const child = cp.spawn(executable, spec.args, { cwd, env: process.env, stdio: "pipe", windowsHide: true });
        spawned = { child, closed: new Promise((done) => child.once("close", () => done())) };
        this.process = child;
        child.stdin.on("error", (error) => this.output.appendLine(`[osc2] writing to the server failed: ${error.message}`));
        child.stderr.on("data", (chunk: Buffer) => {
          const text = chunk.toString();
          stderrTail = (stderrTail + text).slice(-4000);
          this.output.append(text);
        });
        child.once("error", reject);
        child.once("spawn", () => resolve({ reader: child.stdout, writer: guardedWriter(child) }));
      });

    let started = false;
    this.crashes = [];
    const clientOptions: LanguageClientOptions = {
      documentSelector: [
        { scheme: "file", language: "osc2" },
        { scheme: "untitled", language: "osc2" },
      ],
      outputChannel: this.output,
      traceOutputChannel: this.output,
      revealOutputChannelOn: RevealOutputChannelOn.Never,
      initializationOptions: readOptions(),
      initializationFailedHandler: () => false,
      middleware: {
        workspace: {
          configuration: async (params, token, next) => {
            const result = await next(params, token);
            if (!Array.isArray(result)) return result;
            return result.map((value, i) => (params.items[i]?.section === "osc2" ? withOptions(value) : value));
          },
        },
      },
      errorHandler: {
        error: (_error, _message, count): ErrorHandlerResult =>
          count !== undefined && count <= 3 ? { action: ErrorAction.Continue } : { action: ErrorAction.Shutdown },
        closed: async (): Promise<CloseHandlerResult> => {
          if (!started) {
            // Gone before answering `initialize` (typically "No module named
            // osc2lsp"): restarting would only repeat that; doStart reports it.
            // Answer one macrotask later so that the client's start() settles
            // (rejects) before the client forgets its start promise.
            await new Promise((resolve) => setTimeout(resolve, 0));
            return { action: CloseAction.DoNotRestart, handled: true };
          }
          const now = Date.now();
          this.crashes = [...this.crashes.filter((t) => now - t < RESTART_WINDOW_MS), now];
          if (this.crashes.length <= MAX_RESTARTS) return { action: CloseAction.Restart };
          return {
            action: CloseAction.DoNotRestart,
            message: `The OSC2 language server crashed ${this.crashes.length} times in 3 minutes and will not be restarted. Run "OSC2: Restart server" after fixing it.`,
          };
        },
      },
    };

    const client = new Osc2LanguageClient(CLIENT_ID, CLIENT_NAME, serverOptions, clientOptions);
    client.quiet = true;
    this.client = client;
    try {
      await client.start();
      if (!client.isRunning()) throw new Error("the server closed the connection during start-up");
      started = true;
      client.quiet = false;
      this.output.appendLine("[osc2] language server running");
      return;
    } catch (error) {
      const detail = error instanceof Error ? error.message : String(error);
      this.output.appendLine(`[osc2] start failed: ${detail}`);
      if (this.client === client) this.client = undefined;
      this.process = undefined;
      // Did the process end by itself? Then say so, with the last line it printed.
      const exited =
        spawned !== undefined &&
        (await Promise.race([spawned.closed.then(() => true), delay(EXIT_WAIT_MS).then(() => false)]));
      if (spawned && !exited) spawned.child.kill();
      this.reportStartFailure(
        spec,
        exited ? { kind: "exited-during-startup", lastError: lastLine(stderrTail) } : { kind: "spawn-failed", detail },
      );
      try {
        await client.dispose(2000);
      } catch {
        // the client never ran; nothing to clean up
      }
    }
  }

  private async doStop(): Promise<void> {
    const client = this.client;
    const child = this.process;
    this.client = undefined;
    this.process = undefined;
    const ended = child ? exited(child) : Promise.resolve();
    if (client) {
      try {
        await client.dispose(2000);
      } catch (error) {
        this.output.appendLine(`[osc2] stopping the server: ${error instanceof Error ? error.message : String(error)}`);
      }
    }
    if (!child) return;
    // After `exit` the server stops its solver worker and ends by itself: give it the
    // time to (killing it at once used to cut that short). One that does not is not
    // left behind.
    const done = await Promise.race([ended.then(() => true), delay(EXIT_WAIT_MS).then(() => false)]);
    if (done) {
      this.output.appendLine(`[osc2] the server exited (code ${child.exitCode ?? child.signalCode})`);
    } else {
      this.output.appendLine("[osc2] the server did not exit: stopping it");
      child.kill();
    }
  }

  private reportStartFailure(spec: LaunchSpec, failure: StartFailure): void {
    const message = startFailureMessage(spec, failure, vscode.env.remoteName);
    this.output.appendLine(`[osc2] ${message}`);
    void vscode.window.showErrorMessage(message, OPEN_SETTINGS, SHOW_OUTPUT).then((choice) => {
      if (choice === OPEN_SETTINGS) {
        void openServerSettings();
      } else if (choice === SHOW_OUTPUT) {
        this.output.show(true);
      }
    });
  }
}

function lastLine(text: string): string | undefined {
  return text
    .split(/\r?\n/)
    .map((l) => l.trim())
    .filter((l) => l !== "")
    .pop();
}

/** Resolves when the process has exited (at once if it already has). */
function exited(child: cp.ChildProcess): Promise<void> {
  if (child.exitCode !== null || child.signalCode !== null) return Promise.resolve();
  return new Promise((done) => child.once("exit", () => done()));
}

/** A writer to the server's stdin that silently drops data once the process has exited. */
function guardedWriter(child: cp.ChildProcessWithoutNullStreams): Writable {
  const gone = () => child.exitCode !== null || child.signalCode !== null || child.stdin.destroyed;
  return new Writable({
    write(chunk: Buffer | string, encoding: BufferEncoding, callback: (error?: Error | null) => void) {
      if (gone()) return callback();
      child.stdin.write(chunk, encoding, () => callback());
    },
    final(callback: (error?: Error | null) => void) {
      if (!gone()) child.stdin.end();
      callback();
    },
  });
}
