" Vim syntax file
" Language:    thermnet model language (.tnet)
" Reference:   docs/language.md (the whole language: loops, submodels, time,
"              listed output times, data units, signals in expressions, table
"              options, sensors and data statements with column maps included)

if exists('b:current_syntax')
  finish
endif

let s:cpo_save = &cpo
set cpo&vim

syn case match
syn iskeyword @,48-57,_
" Brace blocks (case, series, parallel) span lines: parse from the top (model files are small).
syn sync fromstart

" A statement starts at the beginning of a line or after ';'.
let s:sos = '\%(\%(^\|[;{]\)\s*\)\@<='
" An identifier that is not followed by '=', '(' or '.' (so not a key, a call or a target).
let s:bare = '\<\h\w*\>\%(\s*\%(=\|(\|\.\%(\.\)\@!\)\)\@!'

" ---------------------------------------------------------------- expressions
syn match   tnetOperator     "[-+*/^=]"
syn match   tnetDelimiter    "[,:]"
syn match   tnetTerminator   ";"
syn match   tnetRangeOp      "\.\."
" Numbers: 12 -3.5 1e-3 2.5E+4 (not the digits of an identifier such as node2)
syn match   tnetNumber       "\%([[:alnum:]_)\]]\)\@<!\%([^.]\.\)\@<!-\=\%(\d\+\%(\.\d\+\)\=\|\.\d\+\)\%([eE][-+]\=\d\+\)\=\%([[:alnum:]_]\)\@!"
" Units in square brackets: 160 [W/(m*K)]
syn region  tnetUnit         matchgroup=tnetUnitBracket start="\[" end="\]" oneline
" Strings: \" and \\ are escapes
syn region  tnetString       start=+"+ skip=+\\[\\"]+ end=+"+ end=+$+ oneline contains=tnetEscape
syn match   tnetEscape       +\\[\\"]+ contained
syn match   tnetSignal       "\<\%(step\|pwl\|table\)\ze\s*("
" table(data, "COLUMN" [, hold] [, time = "NAME" [UNIT]] [, separator = "SEP"])
syn match   tnetDataRef      "\%(\<table\s*(\s*\)\@<=\<data\>\ze\s*[,)]"
syn match   tnetFunction     "\<\%(sqrt\|exp\|log10\|log\|sin\|cos\|tan\|abs\|min\|max\|pow\)\ze\s*("
syn match   tnetConstant     "\<\%(pi\|sigma\)\>\%(\s*[=(]\)\@!"
" The simulation time in seconds (in boundary temperatures and source powers)
syn match   tnetTime         "\<time\>\%(\s*[=(]\)\@!"
syn match   tnetContinuation "\\\ze\s*$"
syn keyword tnetTodo         contained TODO FIXME XXX NOTE
syn match   tnetComment      "#.*$" contains=tnetTodo,@Spell

" Keys: NAME = ...
syn match   tnetKey          "\<\h\w*\ze\s*="
" A param's range: param NAME = EXPR range LO .. HI
syn match   tnetRange        "\%(\%(^\|;\)\s*param\>[^;#]*\)\@<=\<range\>\%(\s*[=(]\)\@!"
" Options of a table (after its keys: `time =` is an option there, not a key)
syn match   tnetOption       "\%(\<table\s*([^)]*\)\@<=\<hold\>\%(\s*[=(.]\)\@!"
syn match   tnetOption       "\%(\<table\s*([^)]*\)\@<=\<\%(time\|separator\)\>\ze\s*=\%(=\)\@!"
" OBJECT.KEY in a value: another element's key or a boundary's T (lamp.P, h[2].P)
syn match   tnetKeyRef       "\%([[:alnum:]_.\]]\)\@<!\<\h\w*\%(\[[^]]*\]\)\=\%(\.\h\w*\%(\[[^]]*\]\)\=\)*\.\h\w*\>\%(\s*[=(\[]\|\.\)\@!" contains=tnetIndex

" Indices glued to a name: p[i, j + 1] (a unit follows a number, after a blank)
syn region  tnetIndex        matchgroup=tnetIndexBracket start="\%(\<\h\w*\)\@<=\[" end="\]" oneline contains=@tnetExpr

syn cluster tnetExpr contains=tnetOperator,tnetDelimiter,tnetRangeOp,tnetNumber,tnetUnit,tnetIndex,tnetTime,tnetString,tnetSignal,tnetDataRef,tnetOption,tnetKeyRef,tnetFunction,tnetConstant,tnetContinuation,tnetComment

" ------------------------------------------------------- element statements
" KIND NAME NODE_A [NODE_B] key = EXPR ...
" Any kind (a plugin's too) is recognised by its shape: the first word of a
" statement followed by two more names. Defined first: the statement keywords
" below win over it.
exe 'syn match tnetKind "' . s:sos . '\<\h\w*\>\ze\s\+\h\w*\%(\[[^]]*\]\)\=\s\+' . s:bare . '" nextgroup=tnetElementName skipwhite'
syn match   tnetKind         "\%(\%(^\|[;{]\)\s*\)\@<=\<\%(conductance\|resistor\|conduction\|cylinder_conduction\|contact\|convection\|radiation\|heater\|thermostat\|sensor\|annulus_convection\|cavity_convection\)\>" nextgroup=tnetElementName skipwhite
exe 'syn match tnetElementName "\<\h\w*\>\%(\[[^]]*\]\)\=\%(\s*\%(=\|(\)\)\@!" contained contains=tnetIndex nextgroup=tnetNodeRef,tnetMeanTerms,tnetBlock,tnetHeaderCont skipwhite'
exe 'syn match tnetNodeRef "\<\h\w*\>\%(\[[^]]*\]\)\=\%(\.\h\w*\%(\[[^]]*\]\)\=\)*\%(\s*\%(=\|(\|\.\%(\.\)\@!\)\)\@!" contained contains=tnetIndex nextgroup=tnetNodeRef,tnetBlock,tnetHeaderCont skipwhite'
" a '\' continuation among the terminals: they go on on the next line
syn match   tnetHeaderCont   "\\\ze\s*$" contained nextgroup=tnetNodeRef,tnetBlock skipwhite skipnl
" sensor NAME mean(NODE, ...): a sensor reading the mean of several nodes
syn region  tnetMeanTerms    matchgroup=tnetMean start="\<mean\s*(" end=")" oneline contained contains=tnetMeanNode,tnetDelimiter
syn match   tnetMeanNode     "\<\h\w*\>\%(\[[^]]*\]\)\=\%(\.\h\w*\%(\[[^]]*\]\)\=\)*" contained contains=tnetIndex
" thermostat ... sense = NODE
syn match   tnetNodeRef      "\%(\<sense\s*=\s*\)\@<=\<\h\w*\>\%(\s*[(.]\)\@!"

" Inner elements of series/parallel blocks: { KIND key = EXPR ... ; KIND ... }
syn region  tnetBlock        matchgroup=tnetBrace start="{" end="}" contained contains=tnetInnerKind,tnetKey,tnetTerminator,@tnetExpr
exe 'syn match tnetInnerKind "\%(\%(^\|[{;]\)\s*\)\@<=' . s:bare . '" contained'

" ---------------------------------------------------------------- statements
syn match   tnetStatement    "\%(\%(^\|[;{]\)\s*\)\@<=\<\%(include\|plugin\)\>"
syn match   tnetStatement    "\%(\%(^\|[;{]\)\s*\)\@<=\<\%(model\|const\|param\|node\|boundary\)\>" nextgroup=tnetName skipwhite
syn match   tnetStatement    "\%(\%(^\|[;{]\)\s*\)\@<=\<\%(series\|parallel\)\>" nextgroup=tnetElementName skipwhite
syn match   tnetStatement    "\%(\%(^\|[;{]\)\s*\)\@<=\<case\>" nextgroup=tnetCaseName skipwhite
" require KIND "GROUP"... LO .. HI | max VALUE | min VALUE [from TIME] [in CASE, ...]
syn match   tnetStatement    "\%(\%(^\|[;{]\)\s*\)\@<=\<require\>\ze\s\+\%(band\|gradient\|power\|energy\|margin\)\>" nextgroup=tnetRequireKind skipwhite
syn match   tnetRequireKind  "\<\%(band\|gradient\|power\|energy\|margin\)\>" contained
syn match   tnetRequireWord  "\%(\<require\>.*\)\@<=\<\%(max\|min\|from\|in\)\>"
syn match   tnetStatement    "\%(\%(^\|[;{]\)\s*\)\@<=\<submodel\>\ze\s\+\h\w*\s*(" nextgroup=tnetSubmodelName skipwhite
syn match   tnetSubmodelName "\<\h\w*\>" contained nextgroup=tnetTerminals skipwhite
syn region  tnetTerminals    matchgroup=tnetDelimiter start="(" end=")" oneline contained contains=tnetTerminal,tnetDelimiter
syn match   tnetTerminal     "\<\h\w*\>" contained
" for VAR in LO .. HI [, VAR in LO .. HI] { ... }, at the top level and in cases
syn match   tnetLoop         "\%(\%(^\|[;{]\)\s*\)\@<=\<for\>\ze\s\+\h\w*\s\+in\>" nextgroup=tnetLoopVar skipwhite
syn match   tnetLoopVar      "\<\h\w*\>\ze\s\+in\>" contained nextgroup=tnetLoopIn skipwhite
syn match   tnetLoopIn       "\<in\>" contained
syn match   tnetLoopVar      "\%(\<for\s[^{#]*,\s*\)\@<=\<\h\w*\>\ze\s\+in\>" nextgroup=tnetLoopIn skipwhite
syn match   tnetBrace        "[{}]"
syn match   tnetName         "\<\h\w*\%(\[[^]]*\]\)\=" contained contains=tnetIndex
syn match   tnetCaseName     "\<\h\w*\>" contained nextgroup=tnetCaseBlock skipwhite skipnl

" ---------------------------------------------------------------- case blocks
syn region  tnetCaseBlock    matchgroup=tnetBrace start="{" end="}" contained contains=tnetKey,tnetCaseTarget,tnetCaseKey,tnetSteady,tnetCaseRange,tnetDataOption,tnetDataMap,tnetTerminator,tnetLoop,tnetLoopVar,tnetCaseInner,@tnetExpr
syn region  tnetCaseInner    matchgroup=tnetBrace start="{" end="}" contained contains=tnetKey,tnetCaseTarget,tnetTerminator,tnetLoop,tnetLoopVar,tnetCaseInner,@tnetExpr
" ELEMENT.key = ... / BOUNDARY.T = ...
syn match   tnetCaseTarget   "\<\h\w*\%(\[[^]]*\]\)\=\%(\.\h\w*\%(\[[^]]*\]\)\=\)*\ze\.\h\w*\s*=" contained contains=tnetIndex nextgroup=tnetAccessor
syn match   tnetAccessor     "\." contained nextgroup=tnetKey
syn match   tnetCaseKey      "\<\%(duration\|initial\|output\)\ze\s*=" contained
syn match   tnetCaseKey      +\%(\%(^\|[{;]\)\s*\)\@<=\<data\>\ze\s*"+ contained
syn match   tnetSteady       "\%(\<initial\s*=\s*\)\@<=\<\%(steady\|data\)\>" contained
" NODE.T0 = VALUE range LO .. HI: a start temperature calibrated in this case
syn match   tnetCaseRange    "\<range\>\ze\s[^=(]*\.\." contained
" data "FILE" [UNIT] [time = "COLUMN" [UNIT]] [separator = "SEP"] [{ NODE = COLUMN ... }]
syn match   tnetDataOption   +\%(\<data\s*"[^"]*"\%([^{#;"]\|"[^"]*"\)*\)\@<=\<\%(time\|separator\)\>\ze\s*=+ contained
syn region  tnetDataMap      matchgroup=tnetBrace start=+\%(\<data\s*"[^"]*"\%([^{#;"]\|"[^"]*"\)*\)\@<={+ end=+}+ contained contains=tnetMapTarget,tnetMapColumn,tnetMapMean,tnetString,tnetUnit,tnetNumber,tnetOperator,tnetDelimiter,tnetTerminator,tnetComment,tnetContinuation
syn match   tnetMapTarget    "\<\h\w*\%(\[[^]]*\]\)\=\%(\.\h\w*\%(\[[^]]*\]\)\=\)*\ze\s*=" contained contains=tnetIndex
syn match   tnetMapColumn    "\%(=\s*\)\@<=\<\h\w*\>\%(\s*(\)\@!" contained
syn region  tnetMapMean      matchgroup=tnetMean start="\<mean\s*(" end=")" contained contains=tnetMeanColumn,tnetString,tnetNumber,tnetOperator,tnetDelimiter,tnetUnit
syn match   tnetMeanColumn   "\%([(,]\s*\)\@<=\<\h\w*\>" contained

" ---------------------------------------------------------------- highlighting
hi def link tnetComment      Comment
hi def link tnetTodo         Todo
hi def link tnetStatement    Statement
hi def link tnetRequireKind  Type
hi def link tnetRequireWord  Keyword
hi def link tnetLoop         Repeat
hi def link tnetLoopIn       Repeat
hi def link tnetLoopVar      Identifier
hi def link tnetSubmodelName Function
hi def link tnetTerminal     Identifier
hi def link tnetTime         Constant
hi def link tnetIndexBracket Delimiter
hi def link tnetRange        Keyword
hi def link tnetCaseRange    tnetRange
hi def link tnetOption       Keyword
hi def link tnetDataOption   tnetOption
hi def link tnetDataRef      Constant
hi def link tnetKeyRef       Identifier
hi def link tnetMean         Function
hi def link tnetMeanNode     tnetNodeRef
hi def link tnetMapTarget    Identifier
hi def link tnetMapColumn    String
hi def link tnetMeanColumn   tnetMapColumn
hi def link tnetCaseKey      Keyword
hi def link tnetKind         Type
hi def link tnetInnerKind    tnetKind
hi def link tnetName         Function
hi def link tnetElementName  Function
hi def link tnetCaseName     Function
hi def link tnetNodeRef      Identifier
hi def link tnetCaseTarget   Identifier
hi def link tnetKey          Special
hi def link tnetNumber       Number
hi def link tnetUnit         PreProc
hi def link tnetUnitBracket  Delimiter
hi def link tnetString       String
hi def link tnetEscape       SpecialChar
hi def link tnetSignal       Function
hi def link tnetFunction     Function
hi def link tnetConstant     Constant
hi def link tnetSteady       Constant
hi def link tnetOperator     Operator
hi def link tnetRangeOp      Operator
hi def link tnetDelimiter    Delimiter
hi def link tnetTerminator   Delimiter
hi def link tnetBrace        Delimiter
hi def link tnetAccessor     Delimiter
hi def link tnetContinuation SpecialChar
hi def link tnetHeaderCont   tnetContinuation

let b:current_syntax = 'tnet'

let &cpo = s:cpo_save
unlet s:cpo_save
