using Spectre.Console;

namespace PmacStream.Cli;

/// <summary>
/// Progress for long work: a Spectre.Console bar on an interactive terminal, plain lines (at most one a second and
/// at each whole 10 %) when output is redirected, so logs and CI stay readable.
/// </summary>
internal static class CliProgress
{
    /// <summary>Runs <paramref name="work"/> with a reporter that takes (fraction 0..1, status text).</summary>
    public static async Task<T> RunAsync<T>(string title, CliConsole console, Func<Action<double, string>, Task<T>> work)
    {
        if (console.IsTerminal && AnsiConsole.Profile.Capabilities.Interactive)
        {
            T result = default!;
            await AnsiConsole.Progress()
                .Columns(new TaskDescriptionColumn(), new ProgressBarColumn(), new PercentageColumn(), new ElapsedTimeColumn())
                .StartAsync(async ctx =>
                {
                    var task = ctx.AddTask(Markup.Escape(title), maxValue: 1.0);
                    result = await work((f, s) =>
                    {
                        task.Value = Math.Clamp(f, 0, 1);
                        task.Description = Markup.Escape($"{title} {s}");
                    }).ConfigureAwait(false);
                    task.Value = 1.0;
                }).ConfigureAwait(false);
            return result;
        }

        var lastTenth = -1;
        var lastWrite = DateTime.MinValue;
        var gate = new object();
        return await work((f, s) =>
        {
            lock (gate)
            {
                var tenth = (int)(Math.Clamp(f, 0, 1) * 10);
                var now = DateTime.UtcNow;
                if (tenth != lastTenth || (now - lastWrite).TotalSeconds >= 1)
                {
                    lastTenth = tenth;
                    lastWrite = now;
                    console.Out.WriteLine($"{title} {f * 100,5:0.0}% {s}");
                }
            }
        }).ConfigureAwait(false);
    }
}
