" Vim filetype plugin for thermnet model files (.tnet)
if exists('b:did_ftplugin')
  finish
endif
let b:did_ftplugin = 1

" '#' starts a comment that runs to the end of the line.
setlocal commentstring=#\ %s
setlocal comments=:#
setlocal formatoptions-=t formatoptions+=croql

let b:undo_ftplugin = 'setlocal commentstring< comments< formatoptions<'
