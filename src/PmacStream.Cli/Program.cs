using PmacStream.Cli;

// Exit codes: 0 ok, 1 the input has errors or the job failed, 2 usage or I/O error.
return await CliApp.RunAsync(args).ConfigureAwait(false);
