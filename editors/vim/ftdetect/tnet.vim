" thermnet model files
autocmd BufRead,BufNewFile *.tnet setfiletype tnet
