// A stand-in for the `vscode` module, good enough to activate the bundled
// extension (dist/extension.js) with the real vscode-languageclient inside it.
//
// The parts the extension itself uses are written out and record what
// happens (messages, terminals, opened documents, commands). Everything else
// the language client touches is an "auto" object: any property, call or
// `new` yields another harmless auto object.

import * as fs from "fs";
import Module = require("module");
import { fromRoot } from "./paths";

type Listener<T> = (event: T) => unknown;

function auto(name: string): any {
  const cache = new Map<PropertyKey, unknown>();
  const target = function () {
    /* auto */
  };
  return new Proxy(target, {
    get(t, p) {
      if (p === "then") return undefined; // never look like a promise
      if (p === Symbol.iterator) return function* () {};
      if (p === Symbol.toPrimitive || p === "toString") return () => name;
      if (p === "prototype") return t.prototype;
      if (typeof p === "symbol") return undefined;
      if (!cache.has(p)) cache.set(p, auto(`${name}.${p}`));
      return cache.get(p);
    },
    apply: () => auto(`${name}()`),
    construct: () => auto(`new ${name}`),
  });
}

class Emitter<T> {
  private listeners: Listener<T>[] = [];
  event = (listener: Listener<T>) => {
    this.listeners.push(listener);
    return { dispose: () => (this.listeners = this.listeners.filter((l) => l !== listener)) };
  };
  fire(value: T): void {
    for (const l of [...this.listeners]) l(value);
  }
}

export interface Message {
  severity: "error" | "warning" | "info";
  text: string;
  items: string[];
}

export interface FakeDocument {
  languageId: string;
  isUntitled: boolean;
  isDirty: boolean;
  uri: { fsPath: string; scheme: string; toString(): string };
  save(): Promise<boolean>;
}

export class VscodeMock {
  readonly messages: Message[] = [];
  readonly output: string[] = [];
  readonly terminals: { name: string; cwd?: string; sent: string[]; shown: boolean; exitStatus: undefined }[] = [];
  readonly openedDocuments: { language?: string; content?: string }[] = [];
  readonly executed: { command: string; args: unknown[] }[] = [];
  readonly commands = new Map<string, (...args: unknown[]) => unknown>();
  /** answer given to the next showXxxMessage call, by message text pattern */
  answers: { pattern: RegExp; item: string }[] = [];
  settings: Record<string, unknown> = {};
  activeDocument: FakeDocument | undefined;
  workspaceFolder: string | undefined;
  /** `vscode.env.remoteName`: set for a remote window ("ssh-remote", "wsl", ...) */
  remoteName: string | undefined;
  shell = "/bin/bash";
  private configEmitter = new Emitter<{ affectsConfiguration(section: string): boolean }>();
  readonly module: Record<string, unknown>;

  constructor() {
    const mock = this;
    const show = (severity: Message["severity"]) => async (text: string, ...items: unknown[]) => {
      const labels = items.filter((i): i is string => typeof i === "string");
      mock.messages.push({ severity, text, items: labels });
      return mock.answers.find((a) => a.pattern.test(text))?.item;
    };
    const outputChannel = (name: string) => ({
      name,
      append: (s: string) => mock.output.push(s),
      appendLine: (s: string) => mock.output.push(s),
      replace: () => undefined,
      clear: () => undefined,
      show: () => mock.executed.push({ command: "<show output>", args: [name] }),
      hide: () => undefined,
      dispose: () => undefined,
    });
    const base: Record<string, unknown> = {
      version: "1.82.0",
      env: {
        appName: "mock",
        language: "en",
        get shell() {
          return mock.shell;
        },
        get remoteName() {
          return mock.remoteName;
        },
      },
      ProgressLocation: { SourceControl: 1, Window: 10, Notification: 15 },
      window: {
        createOutputChannel: outputChannel,
        showErrorMessage: show("error"),
        showWarningMessage: show("warning"),
        showInformationMessage: show("info"),
        setStatusBarMessage: () => ({ dispose: () => undefined }),
        withProgress: (_options: unknown, task: (p: unknown, t: unknown) => unknown) =>
          Promise.resolve(task({ report: () => undefined }, auto("token"))),
        get activeTextEditor() {
          return mock.activeDocument ? { document: mock.activeDocument } : undefined;
        },
        visibleTextEditors: [],
        get terminals() {
          return mock.terminals;
        },
        createTerminal: (options: { name: string; cwd?: string }) => {
          const terminal = {
            name: options.name,
            cwd: options.cwd,
            sent: [] as string[],
            shown: false,
            exitStatus: undefined,
            show() {
              this.shown = true;
            },
            sendText(text: string) {
              this.sent.push(text);
            },
            dispose: () => undefined,
          };
          mock.terminals.push(terminal);
          return terminal;
        },
        showTextDocument: async (doc: unknown) => doc,
      },
      workspace: {
        getConfiguration: (section?: string) => ({
          get: (key: string, fallback?: unknown) => mock.configValue(section ? `${section}.${key}` : key, fallback),
          has: (key: string) => mock.configValue(section ? `${section}.${key}` : key) !== undefined,
          inspect: (key: string) => {
            const full = section ? `${section}.${key}` : key;
            return { key: full, defaultValue: mock.defaults[full], globalValue: mock.settings[full] };
          },
          update: async () => undefined,
        }),
        onDidChangeConfiguration: mock.configEmitter.event,
        get workspaceFolders() {
          return mock.workspaceFolder
            ? [{ uri: { fsPath: mock.workspaceFolder, scheme: "file" }, name: "ws", index: 0 }]
            : undefined;
        },
        getWorkspaceFolder: () =>
          mock.workspaceFolder ? { uri: { fsPath: mock.workspaceFolder }, name: "ws", index: 0 } : undefined,
        openTextDocument: async (options: { language?: string; content?: string }) => {
          mock.openedDocuments.push(options);
          return { ...options, uri: { scheme: "untitled" } };
        },
        textDocuments: [],
        notebookDocuments: [],
      },
      commands: {
        registerCommand: (id: string, handler: (...args: unknown[]) => unknown) => {
          mock.commands.set(id, handler);
          return { dispose: () => mock.commands.delete(id) };
        },
        executeCommand: async (command: string, ...args: unknown[]) => {
          mock.executed.push({ command, args });
          return mock.commands.get(command)?.(...args);
        },
      },
    };
    // Every other export of the real API (classes, enums, namespaces) as an auto object.
    const typesFile = fromRoot("node_modules", "@types", "vscode", "index.d.ts");
    const declared = fs.readFileSync(typesFile, "utf8").matchAll(/^\s*export (?:namespace|class|enum|const|function|let) (\w+)/gm);
    for (const [, name] of declared) {
      if (!(name in base)) base[name] = auto(`vscode.${name}`);
      else if (typeof base[name] === "object") base[name] = withFallback(base[name] as object, `vscode.${name}`);
    }
    this.module = base;
  }

  /** Defaults of the contributed settings, as VS Code knows them from package.json. */
  readonly defaults: Record<string, unknown> = Object.fromEntries(
    Object.entries(
      JSON.parse(fs.readFileSync(fromRoot("package.json"), "utf8")).contributes.configuration.properties as Record<
        string,
        { default?: unknown }
      >,
    ).map(([key, schema]) => [key, schema.default]),
  );

  /** A setting's value the way VS Code answers: user value, else default; a section as a nested object. */
  configValue(full: string, fallback?: unknown): unknown {
    if (full in this.settings) return this.settings[full];
    if (full in this.defaults) return this.defaults[full];
    const nested: Record<string, unknown> = {};
    let found = false;
    for (const source of [this.defaults, this.settings]) {
      for (const [key, value] of Object.entries(source)) {
        if (!key.startsWith(full + ".")) continue;
        found = true;
        const parts = key.slice(full.length + 1).split(".");
        let target = nested;
        for (const part of parts.slice(0, -1)) target = (target[part] ??= {}) as Record<string, unknown>;
        target[parts[parts.length - 1]] = value;
      }
    }
    return found ? nested : fallback;
  }

  /** Forget everything recorded so far (the module object itself stays, as the extension holds it). */
  reset(): void {
    this.messages.length = 0;
    this.output.length = 0;
    this.terminals.length = 0;
    this.openedDocuments.length = 0;
    this.executed.length = 0;
    this.answers = [];
    this.settings = {};
    this.activeDocument = undefined;
    this.workspaceFolder = undefined;
    this.remoteName = undefined;
  }

  /** Fire onDidChangeConfiguration for the given setting keys. */
  changeSettings(values: Record<string, unknown>): void {
    Object.assign(this.settings, values);
    const keys = Object.keys(values);
    this.configEmitter.fire({
      affectsConfiguration: (section: string) => keys.some((k) => k === section || k.startsWith(section + ".")),
    });
  }

  messagesMatching(pattern: RegExp): Message[] {
    return this.messages.filter((m) => pattern.test(m.text));
  }
}

function withFallback(object: object, name: string): object {
  return new Proxy(object, {
    get(t, p, receiver) {
      if (p in t || typeof p === "symbol") return Reflect.get(t, p, receiver);
      return auto(`${name}.${String(p)}`);
    },
  });
}

/** Make `require("vscode")` return the mock's module. Call before loading the extension. */
export function installVscodeMock(mock: VscodeMock): void {
  const loader = Module as unknown as { _load: (request: string, ...rest: unknown[]) => unknown };
  const original = loader._load;
  loader._load = function (request: string, ...rest: unknown[]) {
    if (request === "vscode") return mock.module;
    return original.call(this, request, ...rest);
  };
}

export function fakeDocument(fsPath: string, languageId = "osc2"): FakeDocument {
  return {
    languageId,
    isUntitled: false,
    isDirty: false,
    uri: { fsPath, scheme: "file", toString: () => `file://${fsPath}` },
    save: async () => true,
  };
}
