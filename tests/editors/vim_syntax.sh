#!/usr/bin/env bash
# Headless test of editors/vim: opens sample models in Vim (no user config, the
# repository's editors/vim first on 'runtimepath'), and checks the syntax group
# (synIDattr(synID(line, col, 1), "name")) at chosen positions, plus filetype
# detection and the ftplugin's 'commentstring'.
# Needs a Vim with +syntax: Debian's `vim` package (vim-tiny has no syntax).
set -u

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
rtp="$repo/editors/vim"
vim_bin=${VIM_BIN:-vim}

if ! command -v "$vim_bin" >/dev/null 2>&1; then
  echo "vim_syntax.sh: '$vim_bin' not found; install Debian's vim package (apt-get install -y vim)" >&2
  exit 1
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# Checks: FILE|LINE|TEXT|NTH|GROUP. The column is that of the NTH occurrence of TEXT
# on LINE (a word-like TEXT must not touch other word characters); GROUP is the
# expected syntax group there ("" = no syntax item).
cat >"$work/checks" <<'EOF'
two_plates.tnet|1|model|1|tnetStatement
loops.tnet|3|time|1|tnetTime
loops.tnet|4|for|1|tnetLoop
loops.tnet|4|i|1|tnetLoopVar
loops.tnet|4|in|1|tnetLoopIn
loops.tnet|4|j|1|tnetLoopVar
loops.tnet|4|in|2|tnetLoopIn
loops.tnet|4|..|1|tnetRangeOp
loops.tnet|5|node|1|tnetStatement
loops.tnet|5|p|1|tnetName
loops.tnet|5|[|1|tnetIndexBracket
loops.tnet|5|j|1|tnetIndex
loops.tnet|5|12|1|tnetNumber
loops.tnet|7|conductance|1|tnetKind
loops.tnet|7|g|1|tnetElementName
loops.tnet|7|p|1|tnetNodeRef
loops.tnet|7|+|1|tnetOperator
loops.tnet|7|G|1|tnetKey
loops.tnet|8|submodel|1|tnetStatement
loops.tnet|8|box|1|tnetSubmodelName
loops.tnet|8|mount|1|tnetTerminal
loops.tnet|8|lid|1|tnetTerminal
loops.tnet|14|box|1|tnetKind
loops.tnet|14|radio|1|tnetElementName
loops.tnet|14|frame|1|tnetNodeRef
loops.tnet|15|for|1|tnetLoop
loops.tnet|15|b|1|tnetElementName
loops.tnet|15|frame|2|tnetNodeRef
loops.tnet|18|output|1|tnetCaseKey
loops.tnet|19|radio|1|tnetCaseTarget
loops.tnet|19|pcb|1|tnetCaseTarget
loops.tnet|19|T0|1|tnetKey
loops.tnet|20|for|1|tnetLoop
loops.tnet|20|i|1|tnetLoopVar
loops.tnet|20|T0|1|tnetKey
loops.tnet|21|data|1|tnetCaseKey
loops.tnet|21|K|1|tnetUnit
loops.tnet|23|node|1|tnetStatement
two_plates.tnet|1|two_plates|1|tnetName
two_plates.tnet|2|param|1|tnetStatement
two_plates.tnet|2|h_gap|1|tnetName
two_plates.tnet|2|4|1|tnetNumber
two_plates.tnet|2|[|1|tnetUnitBracket
two_plates.tnet|2|W/(m^2*K)|1|tnetUnit
two_plates.tnet|2|]|1|tnetUnitBracket
two_plates.tnet|2|range|1|tnetRange
two_plates.tnet|2|..|1|tnetRangeOp
two_plates.tnet|2|gas gap|1|tnetString
two_plates.tnet|3|boundary|1|tnetStatement
two_plates.tnet|3|T|1|tnetKey
two_plates.tnet|3|pwl|1|tnetSignal
two_plates.tnet|3|-35|1|tnetNumber
two_plates.tnet|4|node|1|tnetStatement
two_plates.tnet|4|plate1|1|tnetName
two_plates.tnet|4|J/K|1|tnetUnit
two_plates.tnet|6|convection|1|tnetKind
two_plates.tnet|6|gap|1|tnetElementName
two_plates.tnet|6|plate1|1|tnetNodeRef
two_plates.tnet|6|plate2|1|tnetNodeRef
two_plates.tnet|6|h|1|tnetKey
two_plates.tnet|7|radiation|1|tnetKind
two_plates.tnet|7|eps1|1|tnetKey
two_plates.tnet|8|series|1|tnetStatement
two_plates.tnet|8|mount|1|tnetElementName
two_plates.tnet|8|ambient|1|tnetNodeRef
two_plates.tnet|8|contact|1|tnetInnerKind
two_plates.tnet|8|conduction|1|tnetInnerKind
two_plates.tnet|8|30e-4|1|tnetNumber
two_plates.tnet|8|mm^2|1|tnetUnit
two_plates.tnet|9|heater|1|tnetKind
two_plates.tnet|10|case|1|tnetStatement
two_plates.tnet|10|warmup|1|tnetCaseName
two_plates.tnet|11|duration|1|tnetCaseKey
two_plates.tnet|11|h|1|tnetUnit
two_plates.tnet|12|film|1|tnetCaseTarget
two_plates.tnet|12|P|1|tnetKey
two_plates.tnet|12|step|1|tnetSignal
two_plates.tnet|13|data|1|tnetCaseKey
two_plates.tnet|13|warmup.csv|1|tnetString
features.tnet|1|#|1|tnetComment
features.tnet|1|Editor|1|tnetComment
features.tnet|2|TODO|1|tnetTodo
features.tnet|4|include|1|tnetStatement
features.tnet|5|plugin|1|tnetStatement
features.tnet|5|libfin.so|1|tnetString
features.tnet|7|const|1|tnetStatement
features.tnet|8|pi|1|tnetConstant
features.tnet|9|# not a comment|1|tnetString
features.tnet|10|0.1|1|tnetNumber
features.tnet|10|..|1|tnetRangeOp
features.tnet|10|0.95|1|tnetNumber
features.tnet|12|node2|1|tnetName
features.tnet|12|T0|1|tnetKey
features.tnet|12|degC|1|tnetUnit
features.tnet|13|2.5E+4|1|tnetNumber
features.tnet|13|-3.5|1|tnetNumber
features.tnet|16|table|1|tnetSignal
features.tnet|18|node2|1|tnetNodeRef
features.tnet|18|k_al|1|
features.tnet|20|\|1|tnetHeaderCont
features.tnet|21|h|1|tnetKey
features.tnet|21|sqrt|1|tnetFunction
features.tnet|21|max|1|tnetFunction
features.tnet|21|1e-3|1|tnetNumber
features.tnet|23|thermostat|1|tnetKind
features.tnet|23|node2|1|tnetNodeRef
features.tnet|24|annulus_convection|1|tnetKind
features.tnet|25|fin_array|1|tnetKind
features.tnet|25|fins|1|tnetElementName
features.tnet|25|;|1|tnetTerminator
features.tnet|25|resistor|1|tnetKind
features.tnet|25|lab|1|tnetNodeRef
features.tnet|26|parallel|1|tnetStatement
features.tnet|26|radiation|1|tnetInnerKind
features.tnet|28|contact|1|tnetInnerKind
features.tnet|28|# glued|1|tnetComment
features.tnet|29|conduction|1|tnetInnerKind
features.tnet|34|initial|1|tnetCaseKey
features.tnet|34|steady|1|tnetSteady
features.tnet|35|output|1|tnetCaseKey
features.tnet|37|ambient|1|tnetCaseTarget
features.tnet|37|sin|1|tnetFunction
features.tnet|38|h_gap|1|tnetKey
features.tnet|39|data|1|tnetCaseKey
features.tnet|43|boundary|1|tnetStatement
features.tnet|44|# comment inside|1|tnetComment
features.tnet|46|data|1|tnetName
features.tnet|46|node|2|tnetStatement
features.tnet|46|range|1|tnetName
features.tnet|47|data|1|tnetNodeRef
features.tnet|47|range|1|tnetNodeRef
features.tnet|48|cavity_convection|1|tnetKind
features.tnet|50|sigma|1|tnetConstant
features.tnet|51|cold|1|tnetCaseName
features.tnet|51|initial|1|tnetCaseKey
features.tnet|51|-10|1|tnetNumber
features.tnet|51|ambient|1|tnetCaseTarget
features.tnet|51|data|1|tnetCaseKey
features.tnet|51|}|1|tnetBrace
features.tnet|52|cavity_convection|1|tnetKind
features.tnet|52|cav2|1|tnetElementName
features.tnet|52|\|1|tnetHeaderCont
features.tnet|53|node2|1|tnetNodeRef
features.tnet|53|data|1|tnetNodeRef
features.tnet|53|H|1|tnetKey
features.tnet|54|\|1|tnetContinuation
features.tnet|55|pi|1|tnetConstant
features.tnet|55|node|1|tnetStatement
features.tnet|55|after|1|tnetName
features.tnet|56|\"|1|tnetEscape
features.tnet|56|quoted|1|tnetString
features.tnet|56|# word|1|tnetString
features.tnet|56|esc_after|1|tnetName
campaign.tnet|8|table|1|tnetSignal
campaign.tnet|8|data|1|tnetDataRef
campaign.tnet|8|t1|1|tnetString
campaign.tnet|9|time|1|tnetOption
campaign.tnet|9|unix s|1|tnetUnit
campaign.tnet|9|separator|1|tnetOption
campaign.tnet|9|degC|1|tnetUnit
campaign.tnet|10|V|1|
campaign.tnet|10|data|1|tnetDataRef
campaign.tnet|10|hold|1|tnetOption
campaign.tnet|11|W/m^2|1|tnetUnit
campaign.tnet|12|lamp|1|tnetKeyRef
campaign.tnet|12|P|2|tnetKeyRef
campaign.tnet|12|h|1|tnetKeyRef
campaign.tnet|12|2|1|tnetNumber
campaign.tnet|12|0.5|1|tnetNumber
campaign.tnet|13|hold|1|tnetOption
campaign.tnet|13|time|1|tnetOption
campaign.tnet|14|sensor|1|tnetKind
campaign.tnet|14|probe|1|tnetElementName
campaign.tnet|14|air|1|tnetNodeRef
campaign.tnet|14|offset|1|tnetKey
campaign.tnet|15|sensor|1|tnetKind
campaign.tnet|15|avg|1|tnetElementName
campaign.tnet|15|mean|1|tnetMean
campaign.tnet|15|air|1|tnetMeanNode
campaign.tnet|15|wall|1|tnetMeanNode
campaign.tnet|15|tau|1|tnetKey
campaign.tnet|16|conductance|1|tnetKind
campaign.tnet|19|initial|1|tnetCaseKey
campaign.tnet|19|data|1|tnetSteady
campaign.tnet|20|wall|1|tnetCaseTarget
campaign.tnet|20|T0|1|tnetKey
campaign.tnet|20|range|1|tnetCaseRange
campaign.tnet|20|..|1|tnetRangeOp
campaign.tnet|21|data|1|tnetCaseKey
campaign.tnet|21|time|1|tnetDataOption
campaign.tnet|21|unix ns|1|tnetUnit
campaign.tnet|21|{|1|tnetBrace
campaign.tnet|21|air|1|tnetMapTarget
campaign.tnet|21|mean|1|tnetMean
campaign.tnet|21|t2|1|tnetMeanColumn
campaign.tnet|21|t3|1|tnetMeanColumn
campaign.tnet|25|K|1|tnetUnit
campaign.tnet|25|time|1|tnetDataOption
campaign.tnet|25|separator|1|tnetDataOption
campaign.tnet|25|;|1|tnetString
campaign.tnet|26|probe|1|tnetMapTarget
campaign.tnet|26|yTi|1|tnetMapColumn
campaign.tnet|26|K|1|tnetUnit
campaign.tnet|27|avg|1|tnetMapTarget
campaign.tnet|27|t2|1|tnetMeanColumn
campaign.tnet|27|2|1|tnetNumber
campaign.tnet|27|t 3 (C)|1|tnetString
campaign.tnet|28|}|1|tnetBrace
campaign.tnet|29|lamp|1|tnetCaseTarget
campaign.tnet|29|P|1|tnetKey
campaign.tnet|29|data|1|tnetDataRef
campaign.tnet|29|hold|1|tnetOption
campaign.tnet|31|node|1|tnetStatement
campaign.tnet|32|tab|1|tnetString
campaign.tnet|32|air|1|tnetMapTarget
campaign.tnet|32|t2|1|tnetMapColumn
campaign.tnet|32|;|2|tnetTerminator
campaign.tnet|32|wall|1|tnetMapTarget
campaign.tnet|32|t3|1|tnetMeanColumn
campaign.tnet|32|}|2|tnetBrace
campaign.tnet|33|after2|1|tnetName
campaign.tnet|33|out|1|tnetKeyRef
campaign.tnet|33|0.9|1|tnetNumber
EOF

cat >"$work/check.vim" <<'EOF'
let s:out = []
let s:pass = 0
let s:fail = 0
function! s:Col(lnum, text, nth) abort
  let s = getline(a:lnum)
  let idx = -1
  let n = 0
  while 1
    let idx = stridx(s, a:text, idx + 1)
    if idx < 0
      return 0
    endif
    if a:text =~# '^\w' && idx > 0 && s[idx - 1] =~# '\w'
      continue
    endif
    if a:text =~# '\w$' && s[idx + len(a:text)] =~# '\w'
      continue
    endif
    let n += 1
    if n == a:nth
      return idx + 1
    endif
  endwhile
endfunction
function! s:Report(ok, msg) abort
  if a:ok
    let s:pass += 1
  else
    let s:fail += 1
    call add(s:out, 'FAIL ' . a:msg)
  endif
endfunction

if !has('syntax')
  call writefile(['FAIL this vim has no +syntax (install the vim package, not vim-tiny)', 'RESULT 0 1'], g:tnet_result)
  qa!
endif

let s:current = ''
for s:row in readfile(g:tnet_checks)
  let [s:file, s:lnum, s:text, s:nth, s:want] = split(s:row, '|', 1)
  if s:file !=# s:current
    execute 'edit ' . fnameescape(g:tnet_samples . '/' . s:file)
    let s:current = s:file
    call s:Report(&filetype ==# 'tnet', s:file . ': filetype is "' . &filetype . '", expected "tnet"')
    call s:Report(get(b:, 'current_syntax', '') ==# 'tnet', s:file . ': b:current_syntax is not "tnet"')
    call s:Report(&commentstring ==# '# %s', s:file . ': commentstring is "' . &commentstring . '", expected "# %s"')
  endif
  let s:col = s:Col(str2nr(s:lnum), s:text, str2nr(s:nth))
  if s:col == 0
    call s:Report(0, printf('%s:%s: "%s" (occurrence %s) not found in: %s', s:file, s:lnum, s:text, s:nth, getline(str2nr(s:lnum))))
    continue
  endif
  let s:got = synIDattr(synID(str2nr(s:lnum), s:col, 1), 'name')
  call s:Report(s:got ==# s:want, printf('%s:%s:%d "%s": expected group "%s", got "%s"', s:file, s:lnum, s:col, s:text, s:want, s:got))
endfor
call add(s:out, printf('RESULT %d %d', s:pass, s:fail))
call writefile(s:out, g:tnet_result)
qa!
EOF

echo "vim_syntax.sh: $("$vim_bin" --version | head -n 1)"
echo "vim_syntax.sh: vim -Es -u NONE -N --cmd 'set rtp^=$rtp' (filetype plugin on, syntax on) on samples/*.tnet"
"$vim_bin" -Es -u NONE -N -i NONE \
  --cmd "set rtp^=$rtp" \
  --cmd "let g:tnet_checks = '$work/checks'" \
  --cmd "let g:tnet_samples = '$here/samples'" \
  --cmd "let g:tnet_result = '$work/result'" \
  -c 'filetype plugin on' -c 'syntax on' \
  -S "$work/check.vim" </dev/null >"$work/vim.log" 2>&1

if [ ! -s "$work/result" ]; then
  echo "vim_syntax.sh: vim wrote no result; its output was:" >&2
  cat "$work/vim.log" >&2
  exit 1
fi

grep '^FAIL ' "$work/result" | sed 's/^FAIL /vim_syntax.sh: FAIL: /' >&2
read -r _ pass fail < <(grep '^RESULT ' "$work/result")
echo "vim: $pass passed, $fail failed"
[ "$fail" -eq 0 ]
