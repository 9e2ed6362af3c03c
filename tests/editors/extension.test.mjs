// Tests of editors/vscode/extension.js without VS Code: the `vscode` module and
// `vscode-languageclient/node` are replaced by stubs, PATH points at temporary folders.
// The language server must start only when a `thermnet` executable is on PATH, and
// the extension must not throw when vscode-languageclient is not installed.
import { test, describe, afterEach } from 'node:test';
import assert from 'node:assert/strict';
import { mkdtempSync, writeFileSync, chmodSync, rmSync } from 'node:fs';
import { tmpdir } from 'node:os';
import { createRequire } from 'node:module';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const require = createRequire(import.meta.url);
const Module = require('node:module');
const here = dirname(fileURLToPath(import.meta.url));
const extensionPath = join(here, '..', '..', 'editors', 'vscode', 'extension.js');

function makeVscodeStub(lines) {
  return {
    window: {
      createOutputChannel: () => ({ appendLine: (l) => lines.push(l), dispose() {} }),
    },
  };
}

function makeClientStub(created) {
  class LanguageClient {
    constructor(id, name, serverOptions, clientOptions) {
      this.args = { id, name, serverOptions, clientOptions };
      created.push(this);
    }
    start() { this.started = true; return Promise.resolve(); }
    stop() { this.stopped = true; return Promise.resolve(); }
  }
  return { LanguageClient, TransportKind: { stdio: 0, ipc: 1, pipe: 2, socket: 3 } };
}

/** Loads extension.js afresh with the given stubs and PATH, and calls activate(). */
function activateWith({ path, clientStub }) {
  const lines = [];
  const origLoad = Module._load;
  const origPath = process.env.PATH;
  Module._load = function (request, parent, isMain) {
    if (request === 'vscode') return makeVscodeStub(lines);
    if (request === 'vscode-languageclient/node') {
      if (clientStub) return clientStub;
      const err = new Error(`Cannot find module '${request}'`);
      err.code = 'MODULE_NOT_FOUND';
      throw err;
    }
    return origLoad.call(this, request, parent, isMain);
  };
  process.env.PATH = path;
  try {
    delete require.cache[require.resolve(extensionPath)];
    const ext = require(extensionPath);
    const context = { subscriptions: [] };
    ext.activate(context);
    return { ext, lines, context };
  } finally {
    Module._load = origLoad;
    process.env.PATH = origPath;
  }
}

const tmpDirs = [];
function tempDir() {
  const d = mkdtempSync(join(tmpdir(), 'tnet-ext-'));
  tmpDirs.push(d);
  return d;
}
afterEach(() => {
  while (tmpDirs.length) rmSync(tmpDirs.pop(), { recursive: true, force: true });
});

describe('extension.js', () => {
  test('no thermnet on PATH: no language client', () => {
    const created = [];
    const { lines } = activateWith({ path: tempDir(), clientStub: makeClientStub(created) });
    assert.equal(created.length, 0);
    assert.ok(lines.some((l) => /not found on PATH/.test(l)), lines.join('\n'));
  });

  test('a non-executable file named thermnet does not count', { skip: process.platform === 'win32' }, () => {
    const dir = tempDir();
    writeFileSync(join(dir, 'thermnet'), '#!/bin/sh\n');
    chmodSync(join(dir, 'thermnet'), 0o644);
    const created = [];
    activateWith({ path: dir, clientStub: makeClientStub(created) });
    assert.equal(created.length, 0);
  });

  test('thermnet on PATH: starts "thermnet lsp" over stdio for tnet documents', { skip: process.platform === 'win32' }, async () => {
    const dir = tempDir();
    const exe = join(dir, 'thermnet');
    writeFileSync(exe, '#!/bin/sh\nexit 0\n');
    chmodSync(exe, 0o755);
    const created = [];
    const stub = makeClientStub(created);
    const { ext } = activateWith({ path: [tempDir(), dir].join(':'), clientStub: stub });
    assert.equal(created.length, 1);
    const { serverOptions, clientOptions } = created[0].args;
    for (const mode of ['run', 'debug']) {
      assert.equal(serverOptions[mode].command, exe);
      assert.deepEqual(serverOptions[mode].args, ['lsp']);
      assert.equal(serverOptions[mode].transport, stub.TransportKind.stdio);
    }
    assert.ok(clientOptions.documentSelector.some((s) => s.language === 'tnet'));
    assert.ok(created[0].started, 'client was not started');
    await ext.deactivate();
    assert.ok(created[0].stopped, 'client was not stopped on deactivate');
  });

  test('a thermnet in a relative PATH entry (a workspace folder) is never run', { skip: process.platform === 'win32' }, () => {
    const dir = tempDir();
    writeFileSync(join(dir, 'thermnet'), '#!/bin/sh\nexit 0\n');
    chmodSync(join(dir, 'thermnet'), 0o755);
    const origCwd = process.cwd();
    process.chdir(dir);
    try {
      const created = [];
      activateWith({ path: '.', clientStub: makeClientStub(created) });
      assert.equal(created.length, 0);
    } finally {
      process.chdir(origCwd);
    }
  });

  test('package.json declares Restricted Mode support (untrustedWorkspaces)', () => {
    const pkg = require(join(here, '..', '..', 'editors', 'vscode', 'package.json'));
    assert.equal(pkg.capabilities.untrustedWorkspaces.supported, true);
    assert.match(pkg.capabilities.untrustedWorkspaces.description, /never loads plugins/);
  });

  test('thermnet on PATH but vscode-languageclient missing: no throw, a message', { skip: process.platform === 'win32' }, () => {
    const dir = tempDir();
    writeFileSync(join(dir, 'thermnet'), '#!/bin/sh\nexit 0\n');
    chmodSync(join(dir, 'thermnet'), 0o755);
    const { lines, ext } = activateWith({ path: dir, clientStub: null });
    assert.ok(lines.some((l) => /vscode-languageclient is not installed/.test(l)), lines.join('\n'));
    assert.equal(ext.deactivate(), undefined);
  });
});
