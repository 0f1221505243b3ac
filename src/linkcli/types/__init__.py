"""One package per problem type; `linkcli.registry` lists them."""
