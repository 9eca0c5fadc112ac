# Bash completion for gvr: the commands, and each command's options as its --help
# lists them, so that it never falls behind the program. Installed as
# share/bash-completion/completions/gvr.
_gvr() {
    local cur="${COMP_WORDS[COMP_CWORD]}" gvr="${COMP_WORDS[0]}" command="" word
    for word in "${COMP_WORDS[@]:1:COMP_CWORD-1}"; do
        case "$word" in
            -*) ;;
            *) command="$word"; break ;;
        esac
    done
    local words
    if [[ -z "$command" ]]; then
        words=$("$gvr" help 2>/dev/null | awk '/^Subcommands:/ {on = 1; next} on && /^  [a-z]/ {print $1}')
    elif [[ "$cur" == -* ]]; then
        words=$("$gvr" "$command" --help 2>/dev/null | grep -oE -- '(^|[ ,])--?[A-Za-z][A-Za-z0-9-]*' | tr -d ' ,')
    else
        mapfile -t COMPREPLY < <(compgen -f -- "$cur")
        return
    fi
    mapfile -t COMPREPLY < <(compgen -W "$words" -- "$cur")
}
complete -o filenames -F _gvr gvr
