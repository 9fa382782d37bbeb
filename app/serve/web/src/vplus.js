// V+ / VAL II highlighting for CodeMirror 6: a stream tokenizer over the interpreter's own word
// lists (vplus-words is generated from interpreter/src/instructions.def and functions.cpp).
import { StreamLanguage } from '@codemirror/language';
import { instructions, functions } from 'vplus-words';

const INSTRUCTIONS = new Set(instructions);
const FUNCTIONS = new Set(functions.map((f) => f.replace(/^[#$]/, '')));
const OPERATORS = new Set(['and', 'or', 'xor', 'not', 'mod', 'bor', 'band', 'bxor', 'com']);

export const vplus = StreamLanguage.define({
  name: 'vplus',
  startState: () => ({}),
  token(stream) {
    if (stream.eatSpace()) return null;
    if (stream.sol() && stream.match(/^\.(program|end)\b/i)) return 'keyword';
    if (stream.peek() === ';') { stream.skipToEnd(); return 'comment'; }
    if (stream.match(/^"([^"]*)"?/)) return 'string';
    if (stream.match(/^\^[HB][0-9A-Fa-f]+/) || stream.match(/^(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?/)) return 'number';
    const word = stream.match(/^[#$]?[A-Za-z_][A-Za-z0-9_.]*/);
    if (word) {
      const w = word[0].toLowerCase(), bare = w.replace(/^[#$]/, '');
      if (INSTRUCTIONS.has(w)) return 'keyword';
      if (OPERATORS.has(w)) return 'operator';
      if (FUNCTIONS.has(bare) && stream.match(/^\s*\(/, false)) return 'variableName.function';
      if (FUNCTIONS.has(bare)) return 'atom';
      return w.startsWith('#') ? 'variableName.special' : w.startsWith('$') ? 'string.special' : 'variableName';
    }
    if (stream.match(/^(<>|<=|>=|==|[-+*/^=<>:])/)) return 'operator';
    stream.next();
    return null;
  },
  languageData: { commentTokens: { line: ';' } },
});
