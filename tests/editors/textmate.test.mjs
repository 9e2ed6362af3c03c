// Headless tests of the VS Code TextMate grammar for thermnet models (.tnet).
// The grammar is loaded with vscode-textmate and vscode-oniguruma (the same engine
// VS Code uses), sample models are tokenized line by line, and the scopes of chosen
// tokens are checked. Run with `node --test` in this folder (see run.sh).
import { test, describe, before } from 'node:test';
import assert from 'node:assert/strict';
import { readFileSync, existsSync } from 'node:fs';
import { createRequire } from 'node:module';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';

const require = createRequire(import.meta.url);
const here = dirname(fileURLToPath(import.meta.url));
const repo = join(here, '..', '..');
const extDir = join(repo, 'editors', 'vscode');
const samplesDir = join(here, 'samples');

const vsctm = require('vscode-textmate');
const oniguruma = require('vscode-oniguruma');

let grammar;

async function loadGrammar() {
  const wasm = readFileSync(require.resolve('vscode-oniguruma/release/onig.wasm'));
  await oniguruma.loadWASM(wasm.buffer.slice(wasm.byteOffset, wasm.byteOffset + wasm.byteLength));
  const pkg = JSON.parse(readFileSync(join(extDir, 'package.json'), 'utf8'));
  const contributed = pkg.contributes.grammars.find((g) => g.language === 'tnet');
  const grammarPath = join(extDir, contributed.path);
  const registry = new vsctm.Registry({
    onigLib: Promise.resolve({
      createOnigScanner: (patterns) => new oniguruma.OnigScanner(patterns),
      createOnigString: (s) => new oniguruma.OnigString(s),
    }),
    loadGrammar: async (scopeName) =>
      scopeName === contributed.scopeName
        ? vsctm.parseRawGrammar(readFileSync(grammarPath, 'utf8'), grammarPath)
        : null,
  });
  const g = await registry.loadGrammar(contributed.scopeName);
  assert.ok(g, `grammar ${contributed.scopeName} did not load from ${grammarPath}`);
  return g;
}

/** Tokenizes a whole text; returns [{text, tokens: [{start, end, text, scopes}]}] per line. */
function tokenize(text) {
  let stack = vsctm.INITIAL;
  return text.split(/\r?\n/).map((line) => {
    const r = grammar.tokenizeLine(line, stack);
    stack = r.ruleStack;
    return {
      text: line,
      tokens: r.tokens.map((t) => ({
        start: t.startIndex,
        end: t.endIndex,
        text: line.slice(t.startIndex, t.endIndex),
        scopes: t.scopes,
      })),
    };
  });
}

const cache = new Map();
function sample(name) {
  if (!cache.has(name)) cache.set(name, tokenize(readFileSync(join(samplesDir, name), 'utf8')));
  return cache.get(name);
}

/**
 * Scopes of the token that covers `text` (its `nth` occurrence, 1-based) on line `line`
 * (1-based) of sample `file`. The token must span exactly `text` unless `partial` is set.
 */
function scopesOf(file, line, text, { nth = 1, partial = false } = {}) {
  const l = sample(file)[line - 1];
  assert.ok(l, `${file} has no line ${line}`);
  // Occurrences of `text`; a word-like end of `text` must not touch another word character.
  const isWord = (c) => c !== undefined && /\w/.test(c);
  const found = [];
  for (let c = l.text.indexOf(text); c >= 0; c = l.text.indexOf(text, c + 1)) {
    if (isWord(text[0]) && isWord(l.text[c - 1])) continue;
    if (isWord(text[text.length - 1]) && isWord(l.text[c + text.length])) continue;
    found.push(c);
  }
  const col = found[nth - 1];
  assert.ok(col !== undefined, `${file}:${line}: "${text}" (occurrence ${nth}) not found in: ${l.text}`);
  const tok = l.tokens.find((t) => t.start <= col && col < t.end);
  const where = `${file}:${line}:${col + 1} "${text}"`;
  if (!partial) {
    assert.equal(tok.text, text, `${where}: token boundaries differ, got token "${tok.text}" [${tok.scopes.join(' ')}]`);
  }
  return { scopes: tok.scopes, where };
}

function expectScope(file, line, text, scope, opts) {
  const { scopes, where } = scopesOf(file, line, text, opts);
  assert.ok(scopes.includes(scope), `${where}: expected scope ${scope}, got [${scopes.join(' ')}]`);
}

function expectNoScope(file, line, text, prefixes, opts) {
  const { scopes, where } = scopesOf(file, line, text, opts);
  for (const p of prefixes) {
    const bad = scopes.find((s) => s === p || s.startsWith(p + '.'));
    assert.ok(!bad, `${where}: must not be scoped ${p}, got [${scopes.join(' ')}]`);
  }
}

before(async () => {
  grammar = await loadGrammar();
});

describe('extension package', () => {
  test('package.json contributes the tnet language, grammar and snippets', () => {
    const pkg = JSON.parse(readFileSync(join(extDir, 'package.json'), 'utf8'));
    assert.equal(pkg.name, 'thermnet');
    const lang = pkg.contributes.languages.find((l) => l.id === 'tnet');
    assert.ok(lang, 'no language with id tnet');
    assert.deepEqual(lang.extensions, ['.tnet']);
    assert.deepEqual(lang.aliases, ['thermnet', 'tnet']);
    assert.ok(existsSync(join(extDir, lang.configuration)), 'language configuration file missing');
    const gr = pkg.contributes.grammars.find((g) => g.language === 'tnet');
    assert.equal(gr.scopeName, 'source.tnet');
    const raw = JSON.parse(readFileSync(join(extDir, gr.path), 'utf8'));
    assert.equal(raw.scopeName, 'source.tnet');
    const sn = pkg.contributes.snippets.find((s) => s.language === 'tnet');
    assert.ok(sn && existsSync(join(extDir, sn.path)), 'snippets file missing');
    assert.ok(pkg.dependencies && pkg.dependencies['vscode-languageclient'], 'vscode-languageclient dependency missing');
    assert.ok(existsSync(join(extDir, pkg.main)), 'main script missing');
  });

  test('every regular expression of the grammar compiles with oniguruma', () => {
    const raw = JSON.parse(readFileSync(join(extDir, 'syntaxes', 'tnet.tmLanguage.json'), 'utf8'));
    const regexes = [];
    (function walk(node, path) {
      if (Array.isArray(node)) return node.forEach((n, i) => walk(n, `${path}[${i}]`));
      if (node && typeof node === 'object') {
        for (const [k, v] of Object.entries(node)) {
          if (['match', 'begin', 'end', 'while'].includes(k) && typeof v === 'string') regexes.push([`${path}.${k}`, v]);
          else walk(v, `${path}.${k}`);
        }
      }
    })(raw, '$');
    assert.ok(regexes.length > 20, `only ${regexes.length} regexes found`);
    for (const [where, re] of regexes) {
      assert.doesNotThrow(() => new oniguruma.OnigScanner([re]).dispose(), `${where}: ${re}`);
    }
    const includes = [...JSON.stringify(raw).matchAll(/"include":"#([^"]+)"/g)].map((m) => m[1]);
    for (const name of includes) assert.ok(raw.repository[name], `#${name} is included but not in the repository`);
  });

  test('language configuration: # comments, brackets, quotes, indentation on {', () => {
    const conf = JSON.parse(readFileSync(join(extDir, 'language-configuration.json'), 'utf8'));
    assert.equal(conf.comments.lineComment, '#');
    for (const pair of [['(', ')'], ['[', ']'], ['{', '}']]) {
      assert.ok(conf.brackets.some((b) => b[0] === pair[0] && b[1] === pair[1]), `bracket ${pair}`);
    }
    assert.ok(conf.autoClosingPairs.some((p) => p.open === '"' && p.close === '"'), 'auto-closing quotes');
    assert.ok(conf.surroundingPairs.length >= 4, 'surrounding pairs');
    assert.ok(new RegExp(conf.indentationRules.increaseIndentPattern).test('case warmup {'));
    assert.ok(new RegExp(conf.indentationRules.decreaseIndentPattern).test('}'));
  });

  test('snippets: node boundary conduction radiation heater thermostat sensor table series case campaign data', () => {
    const snippets = JSON.parse(readFileSync(join(extDir, 'snippets', 'tnet.json'), 'utf8'));
    const prefixes = Object.values(snippets).flatMap((s) => [].concat(s.prefix));
    for (const p of ['node', 'boundary', 'conduction', 'radiation', 'heater', 'thermostat', 'sensor', 'table', 'series', 'case', 'campaign', 'data']) {
      assert.ok(prefixes.includes(p), `no snippet with prefix ${p}`);
    }
    for (const [name, s] of Object.entries(snippets)) {
      assert.ok(Array.isArray(s.body) || typeof s.body === 'string', `snippet ${name} has no body`);
    }
  });

  test('snippet bodies tokenize with the expected kinds and keywords', () => {
    const snippets = JSON.parse(readFileSync(join(extDir, 'snippets', 'tnet.json'), 'utf8'));
    // Replace ${1:default} / ${1|a,b|} / $1 placeholders by their default text, then tokenize.
    const expand = (body) =>
      [].concat(body).join('\n')
        .replace(/\$\{\d+\|([^,|}]*)[^}]*\}/g, '$1')
        .replace(/\$\{\d+:([^}]*)\}/g, '$1')
        .replace(/\$\d+/g, '');
    const first = (body) => tokenize(expand(body))[0].tokens.find((t) => t.text.trim());
    const conduction = Object.values(snippets).find((s) => [].concat(s.prefix).includes('conduction'));
    assert.ok(first(conduction.body).scopes.includes('entity.name.type.element.tnet'));
    const node = Object.values(snippets).find((s) => [].concat(s.prefix).includes('node'));
    assert.ok(first(node.body).scopes.includes('storage.type.tnet'));
    const byPrefix = (p) => Object.values(snippets).find((s) => [].concat(s.prefix).includes(p));
    // Scopes of a word (its first occurrence) in a tokenized text.
    const scopesIn = (lines, word) => {
      for (const l of lines) {
        const t = l.tokens.find((k) => k.text === word);
        if (t) return t.scopes;
      }
      assert.fail(`"${word}" is not a token of: ${lines.map((l) => l.text).join(' / ')}`);
    };
    const sensor = tokenize(expand(byPrefix('sensor').body));
    assert.ok(scopesIn(sensor, 'sensor').includes('entity.name.type.element.tnet'));
    assert.ok(scopesIn(sensor, 'tau').includes('variable.parameter.key.tnet'));
    const table = tokenize('heater h n P = ' + expand(byPrefix('table').body));
    assert.ok(scopesIn(table, 'data').includes('variable.language.data.tnet'));
    assert.ok(scopesIn(table, 'hold').includes('keyword.other.option.tnet'));
    const campaign = tokenize(expand(byPrefix('campaign').body));
    assert.ok(scopesIn(campaign, 'data').includes('constant.language.tnet')); // initial = data
    assert.ok(campaign[3].tokens.find((t) => t.text === 'data').scopes.includes('keyword.other.case.tnet'));
    assert.ok(scopesIn(campaign, 'time').includes('keyword.other.option.tnet'));
    assert.ok(scopesIn(campaign, 'column').includes('variable.other.column.tnet'));
    // the data statement alone, where it stands: in a case
    const data = tokenize('case c {\n' + expand(byPrefix('data').body) + '\n}\nnode after C = 1');
    assert.ok(scopesIn(data, 'data').includes('keyword.other.case.tnet'));
    assert.ok(scopesIn(data, 'node').includes('variable.other.node.tnet'));
    assert.ok(scopesIn(data, 'mean').includes('support.function.mean.tnet'));
    assert.ok(scopesIn(data, 't3').includes('variable.other.column.tnet'));
    assert.ok(scopesIn(data, 'after').includes('entity.name.variable.node.tnet'), 'the case ends after the map');
  });
});

describe('spec example (samples/two_plates.tnet)', () => {
  const F = 'two_plates.tnet';

  test('is the example of the language spec, verbatim (when shared/ is beside the repo)', (t) => {
    const spec = join(repo, '..', 'shared', 'spec', 'language.md');
    if (!existsSync(spec)) return t.skip('shared/spec/language.md not found');
    const md = readFileSync(spec, 'utf8');
    const m = md.match(/## Example\s*\n```[^\n]*\n([\s\S]*?)```/);
    assert.ok(m, 'no example block in the spec');
    assert.equal(readFileSync(join(samplesDir, F), 'utf8'), m[1]);
  });

  test('statement keywords and declared names', () => {
    expectScope(F, 1, 'model', 'keyword.other.tnet');
    expectScope(F, 1, 'two_plates', 'entity.name.namespace.model.tnet');
    expectScope(F, 2, 'param', 'storage.type.tnet');
    expectScope(F, 2, 'h_gap', 'entity.name.variable.param.tnet');
    expectScope(F, 3, 'boundary', 'storage.type.tnet');
    expectScope(F, 3, 'ambient', 'entity.name.variable.boundary.tnet');
    expectScope(F, 4, 'node', 'storage.type.tnet');
    expectScope(F, 4, 'plate1', 'entity.name.variable.node.tnet');
    expectScope(F, 8, 'series', 'storage.type.tnet');
    expectScope(F, 8, 'mount', 'entity.name.function.element.tnet');
    expectScope(F, 10, 'case', 'storage.type.tnet');
    expectScope(F, 10, 'warmup', 'entity.name.section.case.tnet');
  });

  test('range and ..', () => {
    expectScope(F, 2, 'range', 'keyword.other.tnet');
    expectScope(F, 2, '..', 'keyword.operator.range.tnet');
    expectScope(F, 2, '1', 'constant.numeric.tnet', );
    expectScope(F, 2, '10', 'constant.numeric.tnet');
  });

  test('element kinds, element names and node references', () => {
    expectScope(F, 6, 'convection', 'entity.name.type.element.tnet');
    expectScope(F, 6, 'gap', 'entity.name.function.element.tnet');
    expectScope(F, 6, 'plate1', 'variable.other.node.tnet');
    expectScope(F, 6, 'plate2', 'variable.other.node.tnet');
    expectScope(F, 7, 'radiation', 'entity.name.type.element.tnet');
    expectScope(F, 9, 'heater', 'entity.name.type.element.tnet');
    expectScope(F, 9, 'plate1', 'variable.other.node.tnet');
    expectScope(F, 8, 'plate2', 'variable.other.node.tnet');
    expectScope(F, 8, 'ambient', 'variable.other.node.tnet');
    // inner elements of a series block
    expectScope(F, 8, 'contact', 'entity.name.type.element.tnet');
    expectScope(F, 8, 'conduction', 'entity.name.type.element.tnet');
  });

  test('keys, values and expressions', () => {
    expectScope(F, 4, 'C', 'variable.parameter.key.tnet');
    expectScope(F, 5, 'T0', 'variable.parameter.key.tnet');
    expectScope(F, 6, 'h', 'variable.parameter.key.tnet');
    expectScope(F, 6, 'h_gap', 'variable.other.tnet');
    expectNoScope(F, 6, 'h_gap', ['variable.parameter']);
    expectScope(F, 7, 'eps1', 'variable.parameter.key.tnet');
    expectScope(F, 8, 'L', 'variable.parameter.key.tnet');
    expectScope(F, 6, '=', 'keyword.operator.assignment.tnet');
  });

  test('numbers, including signed and exponent forms', () => {
    expectScope(F, 2, '4', 'constant.numeric.tnet');
    expectScope(F, 3, '-35', 'constant.numeric.tnet');
    expectScope(F, 3, '2750', 'constant.numeric.tnet');
    expectScope(F, 7, '0.85', 'constant.numeric.tnet');
    expectScope(F, 8, '30e-4', 'constant.numeric.tnet');
    expectScope(F, 8, '54.8', 'constant.numeric.tnet');
  });

  test('units in brackets', () => {
    expectScope(F, 2, '[', 'meta.unit.tnet');
    expectScope(F, 2, '[', 'punctuation.definition.unit.begin.tnet');
    expectScope(F, 2, 'W/(m^2*K)', 'keyword.other.unit.tnet');
    expectScope(F, 2, 'W/(m^2*K)', 'meta.unit.tnet');
    expectScope(F, 2, ']', 'punctuation.definition.unit.end.tnet');
    expectScope(F, 4, 'J/K', 'keyword.other.unit.tnet');
    expectScope(F, 8, 'mm^2', 'keyword.other.unit.tnet');
    expectScope(F, 11, 'h', 'keyword.other.unit.tnet');
  });

  test('strings, signals and case keys', () => {
    expectScope(F, 2, '"gas gap convection"', 'string.quoted.double.tnet', { partial: true });
    expectScope(F, 2, 'gas gap convection', 'string.quoted.double.tnet');
    expectScope(F, 3, 'pwl', 'support.function.signal.tnet');
    expectScope(F, 3, ':', 'punctuation.separator.key-value.tnet');
    expectScope(F, 12, 'step', 'support.function.signal.tnet');
    expectScope(F, 11, 'duration', 'keyword.other.case.tnet');
    expectScope(F, 12, 'film', 'variable.other.element.tnet');
    expectScope(F, 12, 'P', 'variable.parameter.key.tnet');
    expectScope(F, 13, 'data', 'keyword.other.case.tnet');
    expectScope(F, 13, 'warmup.csv', 'string.quoted.double.tnet');
    expectScope(F, 14, '}', 'punctuation.section.block.end.tnet');
  });
});

describe('tricky cases (samples/features.tnet)', () => {
  const F = 'features.tnet';

  test('comments', () => {
    expectScope(F, 1, '#', 'comment.line.number-sign.tnet');
    expectScope(F, 1, ' Editor test sample', 'comment.line.number-sign.tnet', { partial: true });
    expectScope(F, 28, ' glued', 'comment.line.number-sign.tnet');
    expectScope(F, 44, ' comment inside the signal', 'comment.line.number-sign.tnet');
    // the statement goes on after a comment inside parentheses
    expectScope(F, 45, '1200', 'constant.numeric.tnet');
    expectScope(F, 45, '1200', 'meta.statement.boundary.tnet');
  });

  test('a # inside a string is not a comment', () => {
    expectScope(F, 9, 'gas # not a comment', 'string.quoted.double.tnet');
    expectNoScope(F, 9, 'gas # not a comment', ['comment']);
    expectNoScope(F, 12, 'a node whose name starts like a keyword', ['comment', 'keyword', 'storage']);
    // escaped quotes do not end the string
    expectScope(F, 56, '\\"', 'constant.character.escape.tnet');
    expectScope(F, 56, 'quoted', 'string.quoted.double.tnet');
    expectScope(F, 56, ' # word', 'string.quoted.double.tnet');
    expectNoScope(F, 56, ' # word', ['comment']);
    expectScope(F, 56, 'esc_after', 'entity.name.variable.node.tnet');
  });

  test('include and plugin statements', () => {
    expectScope(F, 4, 'include', 'keyword.other.tnet');
    expectScope(F, 4, 'common/materials.tnet', 'string.quoted.double.tnet');
    expectScope(F, 5, 'plugin', 'keyword.other.tnet');
    expectScope(F, 5, 'plugins/libfin.so', 'string.quoted.double.tnet');
    expectScope(F, 7, 'const', 'storage.type.tnet');
    expectScope(F, 7, 'k_al', 'entity.name.constant.tnet');
  });

  test('keyword-like identifiers used as names are not keywords', () => {
    expectScope(F, 12, 'node2', 'entity.name.variable.node.tnet');
    expectNoScope(F, 12, 'node2', ['keyword', 'storage']);
    expectScope(F, 18, 'node2', 'variable.other.node.tnet');
    expectNoScope(F, 18, 'node2', ['keyword', 'storage', 'constant']);
    expectScope(F, 46, 'data', 'entity.name.variable.node.tnet');
    expectNoScope(F, 46, 'data', ['keyword']);
    expectScope(F, 46, 'range', 'entity.name.variable.node.tnet');
    expectNoScope(F, 46, 'range', ['keyword']);
    expectScope(F, 47, 'data', 'variable.other.node.tnet');
    expectScope(F, 47, 'range', 'variable.other.node.tnet');
    expectNoScope(F, 47, 'range', ['keyword']);
  });

  test('statements separated by ;', () => {
    expectScope(F, 25, ';', 'punctuation.terminator.statement.tnet');
    expectScope(F, 25, 'resistor', 'entity.name.type.element.tnet');
    expectScope(F, 25, 'r1', 'entity.name.function.element.tnet');
    expectScope(F, 25, 'lab', 'variable.other.node.tnet');
    expectScope(F, 46, 'node', 'storage.type.tnet', { nth: 2 });
  });

  test('line continuation', () => {
    expectScope(F, 20, '\\', 'constant.character.escape.line-continuation.tnet');
    expectScope(F, 20, 'air', 'variable.other.node.tnet');
    // the continued line still belongs to the element statement
    expectScope(F, 21, 'h', 'variable.parameter.key.tnet', { nth: 1 });
    expectScope(F, 21, 'h', 'meta.statement.element.tnet', { nth: 1 });
    expectScope(F, 21, 'A', 'meta.statement.element.tnet');
    // and the statement ends at the next newline
    expectScope(F, 22, 'heater', 'entity.name.type.element.tnet');
    expectNoScope(F, 22, 'heater', ['meta.group']);
    // terminals on a continued line are still node references
    expectScope(F, 52, '\\', 'constant.character.escape.line-continuation.tnet');
    expectScope(F, 53, 'node2', 'variable.other.node.tnet');
    expectScope(F, 53, 'data', 'variable.other.node.tnet');
    expectScope(F, 53, 'H', 'variable.parameter.key.tnet');
    // a continued expression; a ';' on the continued line ends the statement
    expectScope(F, 54, '\\', 'constant.character.escape.line-continuation.tnet');
    expectScope(F, 55, '2', 'meta.statement.const.tnet');
    expectScope(F, 55, 'pi', 'constant.language.tnet');
    expectScope(F, 55, 'node', 'storage.type.tnet');
    expectScope(F, 55, 'after', 'entity.name.variable.node.tnet');
  });

  test('core, registered and inferred element kinds', () => {
    expectScope(F, 18, 'conduction', 'entity.name.type.element.tnet');
    expectScope(F, 23, 'thermostat', 'entity.name.type.element.tnet');
    expectScope(F, 24, 'annulus_convection', 'entity.name.type.element.tnet');
    expectScope(F, 48, 'cavity_convection', 'entity.name.type.element.tnet');
    // a registered kind whose terminals are on the next line: known by name, not by shape
    expectScope(F, 52, 'cavity_convection', 'entity.name.type.element.tnet');
    expectScope(F, 52, 'cav2', 'entity.name.function.element.tnet');
    // a plugin kind, inferred from "KIND NAME NODE ..."
    expectScope(F, 25, 'fin_array', 'entity.name.type.element.tnet');
    expectScope(F, 25, 'fins', 'entity.name.function.element.tnet');
    expectScope(F, 25, 'shell', 'variable.other.node.tnet');
    expectScope(F, 25, 'n', 'variable.parameter.key.tnet');
    // parallel block with inner kinds
    expectScope(F, 26, 'parallel', 'storage.type.tnet');
    expectScope(F, 26, 'convection', 'entity.name.type.element.tnet');
    expectScope(F, 26, 'radiation', 'entity.name.type.element.tnet');
    expectScope(F, 26, 'GR', 'variable.parameter.key.tnet');
    // multi-line series block
    expectScope(F, 29, 'conduction', 'entity.name.type.element.tnet');
    expectScope(F, 29, 'conduction', 'meta.block.combination.tnet');
  });

  test('thermostat sense refers to a node', () => {
    expectScope(F, 23, 'sense', 'variable.parameter.key.tnet');
    expectScope(F, 23, 'node2', 'variable.other.node.tnet');
    expectScope(F, 23, 'on', 'variable.parameter.key.tnet');
  });

  test('numbers', () => {
    expectScope(F, 13, '2.5E+4', 'constant.numeric.tnet');
    expectScope(F, 13, '-3.5', 'constant.numeric.tnet');
    expectScope(F, 21, '1e-3', 'constant.numeric.tnet');
    expectScope(F, 10, '0.1', 'constant.numeric.tnet');
    expectScope(F, 10, '..', 'keyword.operator.range.tnet');
    expectScope(F, 10, '0.95', 'constant.numeric.tnet');
    expectScope(F, 15, '-5', 'constant.numeric.tnet');
    // digits inside identifiers are not numbers
    expectNoScope(F, 19, 'eps1', ['constant']);
    expectNoScope(F, 12, 'T0', ['constant']);
  });

  test('signals, math functions and constants', () => {
    expectScope(F, 15, 'step', 'support.function.signal.tnet');
    expectScope(F, 16, 'table', 'support.function.signal.tnet');
    expectScope(F, 16, 'lab.csv', 'string.quoted.double.tnet');
    expectScope(F, 22, 'pwl', 'support.function.signal.tnet');
    expectScope(F, 21, 'sqrt', 'support.function.math.tnet');
    expectScope(F, 21, 'max', 'support.function.math.tnet');
    expectScope(F, 37, 'sin', 'support.function.math.tnet');
    expectScope(F, 8, 'pi', 'constant.language.tnet');
    expectScope(F, 50, 'sigma', 'constant.language.tnet');
    expectScope(F, 8, '*', 'keyword.operator.arithmetic.tnet');
    expectScope(F, 8, '^', 'keyword.operator.arithmetic.tnet');
    expectScope(F, 15, '[', 'meta.unit.tnet');
    expectScope(F, 15, 's', 'keyword.other.unit.tnet', { nth: 1 });
  });

  test('case block', () => {
    expectScope(F, 33, 'duration', 'keyword.other.case.tnet');
    expectScope(F, 34, 'initial', 'keyword.other.case.tnet');
    expectScope(F, 34, 'steady', 'constant.language.tnet');
    expectScope(F, 35, 'output', 'keyword.other.case.tnet');
    expectScope(F, 37, 'ambient', 'variable.other.element.tnet');
    expectScope(F, 37, '.', 'punctuation.accessor.tnet');
    expectScope(F, 37, 'T', 'variable.parameter.key.tnet');
    expectScope(F, 38, 'h_gap', 'variable.parameter.key.tnet');
    expectScope(F, 39, 'data', 'keyword.other.case.tnet');
    // a one-line case with ';' separators
    expectScope(F, 51, 'cold', 'entity.name.section.case.tnet');
    expectScope(F, 51, 'duration', 'keyword.other.case.tnet');
    expectScope(F, 51, 'initial', 'keyword.other.case.tnet');
    expectScope(F, 51, '-10', 'constant.numeric.tnet');
    expectScope(F, 51, 'degC', 'keyword.other.unit.tnet');
    expectScope(F, 51, 'ambient', 'variable.other.element.tnet');
    expectScope(F, 51, 'data', 'keyword.other.case.tnet');
    expectScope(F, 51, '}', 'punctuation.section.block.end.tnet');
    // after the case block, top-level statements are recognised again
    expectScope(F, 43, 'boundary', 'storage.type.tnet');
    expectNoScope(F, 43, 'boundary', ['meta.block']);
  });
});

describe('loops, submodels and time (samples/loops.tnet)', () => {
  const F = 'loops.tnet';

  test('for blocks: keywords, loop variables, ranges and indexed names', () => {
    expectScope(F, 4, 'for', 'keyword.control.loop.tnet');
    expectScope(F, 4, 'i', 'variable.other.loop.tnet');
    expectScope(F, 4, 'in', 'keyword.control.loop.tnet', { nth: 1 });
    expectScope(F, 4, 'j', 'variable.other.loop.tnet');
    expectScope(F, 4, '..', 'keyword.operator.range.tnet');
    expectScope(F, 4, '{', 'punctuation.section.block.begin.tnet');
    expectNoScope(F, 4, 'for', ['entity.name.type.element']);
    expectScope(F, 5, 'node', 'storage.type.tnet');
    expectScope(F, 5, '[', 'punctuation.section.brackets.begin.tnet');
    expectScope(F, 5, 'i', 'meta.index.tnet');
    expectNoScope(F, 5, 'i', ['meta.unit', 'keyword.other.unit']);
    expectScope(F, 6, '}', 'punctuation.section.block.end.tnet');
  });

  test('a one-line loop body: the element, its indexed name and nodes', () => {
    expectScope(F, 7, 'conductance', 'entity.name.type.element.tnet');
    expectScope(F, 7, 'g', 'entity.name.function.element.tnet');
    expectScope(F, 7, 'p', 'variable.other.node.tnet', { nth: 1 });
    expectScope(F, 7, '+', 'meta.index.tnet');
    expectScope(F, 7, 'G', 'variable.parameter.key.tnet');
  });

  test('submodel definitions, terminals, and instances', () => {
    expectScope(F, 8, 'submodel', 'keyword.other.tnet');
    expectScope(F, 8, 'box', 'entity.name.type.submodel.tnet');
    expectScope(F, 8, 'mount', 'variable.parameter.terminal.tnet');
    expectScope(F, 8, 'lid', 'variable.parameter.terminal.tnet');
    expectScope(F, 9, 'param', 'storage.type.tnet');
    expectScope(F, 11, 'conductance', 'entity.name.type.element.tnet');
    expectScope(F, 14, 'box', 'entity.name.type.element.tnet');
    expectScope(F, 14, 'radio', 'entity.name.function.element.tnet');
    expectScope(F, 15, 'box', 'entity.name.type.element.tnet');
    expectScope(F, 15, 'b', 'entity.name.function.element.tnet');
    expectScope(F, 15, 'k', 'meta.index.tnet', { nth: 2 });
  });

  test('time in expressions', () => {
    expectScope(F, 3, 'time', 'variable.language.time.tnet');
  });

  test('case blocks: listed output times, dotted targets, loops and a data unit', () => {
    expectScope(F, 18, 'output', 'keyword.other.case.tnet');
    expectScope(F, 18, ',', 'punctuation.separator.delimiter.tnet', { nth: 2 });
    expectScope(F, 19, 'T0', 'variable.parameter.key.tnet');
    expectScope(F, 19, 'radio.pcb', 'variable.other.element.tnet');
    expectScope(F, 20, 'for', 'keyword.control.loop.tnet');
    expectScope(F, 20, 'i', 'variable.other.loop.tnet');
    expectScope(F, 20, 'T0', 'variable.parameter.key.tnet');
    expectScope(F, 21, 'data', 'keyword.other.case.tnet');
    expectScope(F, 21, 'K', 'keyword.other.unit.tnet');
    // the loop's braces inside the case do not end the case block
    expectScope(F, 21, 'data', 'meta.block.case.tnet');
    expectScope(F, 23, 'node', 'storage.type.tnet');
    expectNoScope(F, 23, 'node', ['meta.block']);
  });
});

describe('real campaigns (samples/campaign.tnet)', () => {
  const F = 'campaign.tnet';

  test('table(data, ...): the case data file as the first argument', () => {
    expectScope(F, 8, 'table', 'support.function.signal.tnet');
    expectScope(F, 8, 'data', 'variable.language.data.tnet');
    expectNoScope(F, 8, 'data', ['keyword.other.case', 'variable.other']);
    expectScope(F, 8, 't1', 'string.quoted.double.tnet');
    expectScope(F, 8, ')', 'punctuation.section.parens.end.tnet');
    expectScope(F, 29, 'data', 'variable.language.data.tnet'); // in a case override
  });

  test('table options: hold, time = "COLUMN" [UNIT], separator = "SEP", a unit after the table', () => {
    expectScope(F, 10, 'hold', 'keyword.other.option.tnet');
    expectScope(F, 10, 'hold', 'meta.table.tnet');
    expectScope(F, 13, 'hold', 'keyword.other.option.tnet');
    expectScope(F, 9, 'time', 'keyword.other.option.tnet');
    expectNoScope(F, 9, 'time', ['variable.language', 'variable.parameter']);
    expectScope(F, 9, 'unix s', 'keyword.other.unit.tnet');
    expectScope(F, 9, 'separator', 'keyword.other.option.tnet');
    expectScope(F, 9, ';', 'string.quoted.double.tnet');
    expectScope(F, 9, 'degC', 'keyword.other.unit.tnet');
    expectNoScope(F, 9, 'degC', ['meta.table']); // the unit follows the table
    expectScope(F, 13, 'time', 'keyword.other.option.tnet');
    expectScope(F, 13, 'h', 'keyword.other.unit.tnet');
  });

  test('signals inside expressions', () => {
    expectScope(F, 10, 'V', 'variable.other.tnet');
    expectScope(F, 10, '*', 'keyword.operator.arithmetic.tnet', { nth: 2 });
    expectScope(F, 10, 'table', 'support.function.signal.tnet');
    expectScope(F, 11, 'Aw', 'variable.other.tnet');
    expectScope(F, 11, 'W/m^2', 'keyword.other.unit.tnet');
    expectScope(F, 13, 'W/kW', 'keyword.other.unit.tnet');
  });

  test("references to another element's key: lamp.P, h[2].P, out.T", () => {
    expectScope(F, 12, 'lamp', 'variable.other.element.tnet');
    expectScope(F, 12, '.', 'punctuation.accessor.tnet', { nth: 2 });
    expectScope(F, 12, 'P', 'variable.parameter.key.tnet', { nth: 2 });
    expectScope(F, 12, 'h', 'variable.other.element.tnet');
    expectScope(F, 12, '2', 'meta.index.tnet');
    expectScope(F, 12, 'P', 'variable.parameter.key.tnet', { nth: 3 });
    expectScope(F, 33, 'out', 'variable.other.element.tnet');
    expectScope(F, 33, 'T', 'variable.parameter.key.tnet', { nth: 2 });
    // a number with a fraction is not a reference
    expectScope(F, 33, '0.9', 'constant.numeric.tnet');
  });

  test('the sensor kind and its mean(...) terminals', () => {
    expectScope(F, 14, 'sensor', 'entity.name.type.element.tnet');
    expectScope(F, 14, 'probe', 'entity.name.function.element.tnet');
    expectScope(F, 14, 'air', 'variable.other.node.tnet');
    expectScope(F, 14, 'tau', 'variable.parameter.key.tnet');
    expectScope(F, 14, 'offset', 'variable.parameter.key.tnet');
    expectScope(F, 15, 'sensor', 'entity.name.type.element.tnet');
    expectScope(F, 15, 'avg', 'entity.name.function.element.tnet');
    expectScope(F, 15, 'mean', 'support.function.mean.tnet');
    expectScope(F, 15, 'air', 'variable.other.node.tnet');
    expectScope(F, 15, 'wall', 'variable.other.node.tnet');
    expectScope(F, 15, 'tau', 'variable.parameter.key.tnet');
    expectScope(F, 16, 'conductance', 'entity.name.type.element.tnet');
  });

  test('case settings: initial = data, NODE.T0 = VALUE range LO .. HI', () => {
    expectScope(F, 19, 'initial', 'keyword.other.case.tnet');
    expectScope(F, 19, 'data', 'constant.language.tnet');
    expectScope(F, 20, 'wall', 'variable.other.element.tnet');
    expectScope(F, 20, 'T0', 'variable.parameter.key.tnet');
    expectScope(F, 20, 'range', 'keyword.other.tnet');
    expectScope(F, 20, '..', 'keyword.operator.range.tnet');
    expectScope(F, 20, '30', 'constant.numeric.tnet');
  });

  test('data statements: options and column maps on one line and over several', () => {
    expectScope(F, 21, 'data', 'keyword.other.case.tnet');
    expectScope(F, 21, 'time', 'keyword.other.option.tnet');
    expectScope(F, 21, 'time', 'string.quoted.double.tnet', { nth: 2 });
    expectScope(F, 21, 'unix ns', 'keyword.other.unit.tnet');
    expectScope(F, 21, '{', 'punctuation.section.block.begin.tnet');
    expectScope(F, 21, 'air', 'variable.other.node.tnet');
    expectScope(F, 21, 'mean', 'support.function.mean.tnet');
    expectScope(F, 21, 't2', 'variable.other.column.tnet');
    expectScope(F, 21, 't3', 'variable.other.column.tnet');
    expectScope(F, 21, '}', 'meta.block.data.tnet');
    expectScope(F, 22, '}', 'punctuation.section.block.end.tnet');
    expectNoScope(F, 22, '}', ['meta.block.data']);
    expectScope(F, 25, 'K', 'keyword.other.unit.tnet');
    expectScope(F, 25, 'separator', 'keyword.other.option.tnet');
    expectScope(F, 25, '{', 'meta.block.data.tnet');
    expectScope(F, 26, 'probe', 'variable.other.node.tnet');
    expectScope(F, 26, 'yTi', 'variable.other.column.tnet');
    expectScope(F, 26, 'K', 'keyword.other.unit.tnet');
    expectScope(F, 27, 'avg', 'variable.other.node.tnet');
    expectScope(F, 27, 't2', 'variable.other.column.tnet');
    expectScope(F, 27, '2', 'constant.numeric.tnet'); // a weight (the 2 of t2 is part of a word)
    expectScope(F, 27, 't 3 (C)', 'string.quoted.double.tnet');
    expectScope(F, 27, '1', 'constant.numeric.tnet');
    // after the map, the case goes on and its overrides are overrides again
    expectScope(F, 29, 'lamp', 'variable.other.element.tnet');
    expectNoScope(F, 29, 'lamp', ['meta.block.data', 'meta.statement.data']);
    expectScope(F, 29, 'hold', 'keyword.other.option.tnet');
    expectScope(F, 31, 'node', 'storage.type.tnet');
    expectNoScope(F, 31, 'node', ['meta.block']);
    // a one-line case: ';' between map entries, the map's '}' then the case's
    expectScope(F, 32, 'tab', 'string.quoted.double.tnet');
    expectScope(F, 32, 'air', 'variable.other.node.tnet');
    expectScope(F, 32, ';', 'punctuation.terminator.statement.tnet', { nth: 2 });
    expectScope(F, 32, 'wall', 'variable.other.node.tnet');
    expectScope(F, 32, '}', 'meta.block.data.tnet');
    expectScope(F, 32, '}', 'punctuation.section.block.end.tnet', { nth: 2 });
    expectNoScope(F, 32, '}', ['meta.block.data'], { nth: 2 });
    expectScope(F, 33, 'after2', 'entity.name.variable.node.tnet');
  });
});
