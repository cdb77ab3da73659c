using System.Diagnostics;
using System.Globalization;
using System.Text.Json;
using PmacStream.Hmi;
using Xunit.Abstractions;

namespace PmacStream.WinForms.UiTests;

/// <summary>
/// The test's hands and eyes on the running form: real X input (xdotool) at the places <see cref="HmiLayout"/>
/// gives, the form's scripted mode, its snapshots of what it shows, and screenshots of the X screen.
/// Every wait is bounded.
/// </summary>
internal sealed class HmiScreen(string channelDirectory, string display, string screenshotDirectory, ITestOutputHelper output)
{
    /// <summary>Longest wait for one step's effect on the screen.</summary>
    public static readonly TimeSpan StepTimeout = TimeSpan.FromSeconds(45);

    private readonly Dictionary<string, string> _x = new() { ["DISPLAY"] = display };
    private int _commands;
    private UiSnapshot? _last;

    /// <summary>The latest snapshot the form wrote (null before the first).</summary>
    public UiSnapshot? Latest => Read() ?? _last;

    /// <summary>Waits for a snapshot that satisfies <paramref name="condition"/>; fails with the last one seen.</summary>
    public UiSnapshot WaitFor(string what, Func<UiSnapshot, bool> condition, TimeSpan? timeout = null)
    {
        var clock = Stopwatch.StartNew();
        var limit = timeout ?? StepTimeout;
        while (true)
        {
            if (Read() is { } s)
            {
                if (s.DialogTitle is not null && s.Errors.Count > 0 && s.DialogText == s.Errors[^1])
                {
                    throw new InvalidOperationException($"waiting for {what}: the form shows an error: {s.DialogText}");
                }

                if (condition(s))
                {
                    output.WriteLine($"  {what}: after {clock.Elapsed.TotalSeconds:0.0} s");
                    return s;
                }
            }

            if (clock.Elapsed > limit)
            {
                throw new TimeoutException($"waiting for {what}: not within {limit.TotalSeconds:0} s; the screen showed: {Describe(_last)}");
            }

            Thread.Sleep(100);
        }
    }

    /// <summary>Waits until the form's streaming timer has ticked <paramref name="ticks"/> more times.</summary>
    public UiSnapshot WaitTicks(int ticks)
    {
        var from = WaitFor("a snapshot", _ => true).Ticks;
        return WaitFor($"{ticks} ticks of timer1", s => s.Ticks >= from + ticks);
    }

    /// <summary>Scripted mode: the form carries out <paramref name="command"/> (e.g. <c>click btnAbort</c>).</summary>
    public UiSnapshot Script(string command)
    {
        var n = Send(command);
        var s = WaitFor($"scripted '{command}'", x => x.LastCommand >= n);
        s.CommandError.Should().BeNull($"the form carried out '{command}'");
        return s;
    }

    /// <summary>Hands the form a scripted command without waiting for its effect (e.g. <c>close</c>); returns its number.</summary>
    public int Send(string command)
    {
        var n = ++_commands;
        var temp = Path.Combine(channelDirectory, $"writing-{n:000000}");
        File.WriteAllText(temp, command);
        File.Move(temp, Path.Combine(channelDirectory, $"cmd-{n:000000}.txt"));
        return n;
    }

    /// <summary>Real input: a left click at the middle of a control's layout box (inside <paramref name="group"/> when given).</summary>
    public void Click(LayoutBox box, LayoutBox? group = null)
    {
        var (x, y) = ScreenPoint(box, group);
        Xdotool("mousemove", x.ToString(CultureInfo.InvariantCulture), y.ToString(CultureInfo.InvariantCulture), "click", "1");
    }

    /// <summary>
    /// Real input: clicks a button and waits for what the click does; a click the busy form did not take (seen under
    /// heavy load: the pointer event arrives while Wine is still painting) is repeated, up to three clicks in all. Only
    /// for buttons the click disables or replaces (Hold, Abort), so a late first click cannot act twice.
    /// </summary>
    public UiSnapshot ClickUntil(string what, LayoutBox box, Func<UiSnapshot, bool> condition, LayoutBox? group = null)
    {
        for (var attempt = 1; ; attempt++)
        {
            Click(box, group);
            try
            {
                return WaitFor(what, condition, attempt < 3 ? TimeSpan.FromSeconds(10) : StepTimeout);
            }
            catch (TimeoutException) when (attempt < 3)
            {
                output.WriteLine($"  {what}: not after click {attempt} (10 s), clicking again");
            }
        }
    }

    /// <summary>Real input: moves the pointer to a point (the keyboard goes to the window under it: no window manager).</summary>
    public void PointAt(int x, int y) =>
        Xdotool("mousemove", x.ToString(CultureInfo.InvariantCulture), y.ToString(CultureInfo.InvariantCulture));

    /// <summary>Real input: types text.</summary>
    public void Type(string text) => Xdotool("type", "--delay", "15", text);

    /// <summary>Real input: presses keys (xdotool names: Return, Down, ctrl+a).</summary>
    public void Key(params string[] keys) => Xdotool(["key", .. keys]);

    /// <summary>A control's middle on the screen.</summary>
    public (int X, int Y) ScreenPoint(LayoutBox box, LayoutBox? group = null)
    {
        var s = _last ?? WaitFor("a snapshot", _ => true);
        return (s.ClientX + (group?.X ?? 0) + box.X + (box.Width / 2), s.ClientY + (group?.Y ?? 0) + box.Y + (box.Height / 2));
    }

    /// <summary>Finds a top-level window by its exact title (xdotool, as no window manager lists it); null when none.</summary>
    public (int X, int Y, int Width, int Height)? FindWindow(string title)
    {
        var (exit, ids, _) = Tool.TryRun("xdotool", ["search", "--name", title], TimeSpan.FromSeconds(10), _x);
        if (exit != 0)
        {
            return null;
        }

        foreach (var id in ids.Split('\n', StringSplitOptions.RemoveEmptyEntries | StringSplitOptions.TrimEntries))
        {
            var info = Tool.TryRun("xwininfo", ["-id", id], TimeSpan.FromSeconds(10), _x).Output;
            if (!info.Contains($"\"{title}\"", StringComparison.Ordinal) || !info.Contains("Map State: IsViewable", StringComparison.Ordinal))
            {
                continue;
            }

            int Field(string name) => int.Parse(info.Split('\n').First(l => l.Trim().StartsWith(name, StringComparison.Ordinal)).Split(':')[1].Trim(), CultureInfo.InvariantCulture);
            return (Field("Absolute upper-left X"), Field("Absolute upper-left Y"), Field("Width"), Field("Height"));
        }

        return null;
    }

    /// <summary>Waits (bounded) for a window titled <paramref name="title"/> to be on the screen.</summary>
    public (int X, int Y, int Width, int Height) WaitForWindow(string title) =>
        WaitForX($"a window titled '{title}'", () => FindWindow(title));

    /// <summary>
    /// Takes a screenshot of the form's area of the X screen, saves it as <paramref name="name"/>.png and checks it is
    /// not blank (many colours, as text and controls give).
    /// </summary>
    public string Screenshot(string name)
    {
        var s = _last ?? WaitFor("a snapshot", _ => true);
        var path = Path.Combine(screenshotDirectory, name + ".png");
        Tool.Run("import", ["-window", "root", "-crop", $"{s.ClientWidth}x{s.ClientHeight}+{s.ClientX}+{s.ClientY}", "+repage", path], TimeSpan.FromSeconds(30), _x);
        var colours = int.Parse(Tool.Run("identify", ["-format", "%k", path], TimeSpan.FromSeconds(30)).Trim(), CultureInfo.InvariantCulture);
        colours.Should().BeGreaterThan(32, $"{name}.png shows the form, not a blank screen");
        output.WriteLine($"  screenshot {name}.png: {colours} colours");
        return path;
    }

    /// <summary>
    /// Takes screenshots until <paramref name="painted"/> holds for one (at most <paramref name="attempts"/>, 0.3 s
    /// apart) and returns the last: the lists repaint as M0 moves on, and a screenshot may catch one half drawn.
    /// </summary>
    public string ScreenshotWhenPainted(string name, Func<string, bool> painted, int attempts = 8)
    {
        for (var attempt = 1; ; attempt++)
        {
            var shot = Screenshot(name);
            if (painted(shot) || attempt >= attempts)
            {
                return shot;
            }

            output.WriteLine("  (a list was being repainted; again)");
            Thread.Sleep(300);
        }
    }

    /// <summary>Pixels of colour <paramref name="hex"/> (e.g. <c>#FFD700</c>) inside a region of a screenshot.</summary>
    public static int CountColour(string png, LayoutBox region, string hex)
    {
        var text = Tool.Run("convert", [png, "-crop", $"{region.Width}x{region.Height}+{region.X}+{region.Y}", "+repage", "txt:-"], TimeSpan.FromSeconds(30));
        return text.Split('\n').Count(l => l.Contains(hex, StringComparison.OrdinalIgnoreCase));
    }

    /// <summary>One line about a snapshot, for failure messages.</summary>
    public static string Describe(UiSnapshot? s) => s is null
        ? "(no snapshot yet)"
        : $"ticks {s.Ticks}, status [{string.Join(" | ", s.Status)}], executing {s.ExecutingLine}, dialog '{s.DialogTitle}', errors [{string.Join(" | ", s.Errors)}], log ..{string.Join(" / ", s.LogTail.TakeLast(3))}";

    private UiSnapshot? Read()
    {
        var path = Path.Combine(channelDirectory, "state.json");
        try
        {
            // The form replaces the file whole; a read that meets the swap just tries again next time.
            var s = JsonSerializer.Deserialize(File.ReadAllText(path), UiSnapshotJson.Default.UiSnapshot);
            if (s is not null)
            {
                _last = s;
            }

            return s;
        }
        catch (Exception e) when (e is IOException or JsonException)
        {
            return null;
        }
    }

    private static (int X, int Y, int Width, int Height) WaitForX(string what, Func<(int X, int Y, int Width, int Height)?> find)
    {
        var clock = Stopwatch.StartNew();
        while (clock.Elapsed < StepTimeout)
        {
            if (find() is { } w)
            {
                return w;
            }

            Thread.Sleep(100);
        }

        throw new TimeoutException($"no {what} on the X screen within {StepTimeout.TotalSeconds:0} s");
    }

    private void Xdotool(params string[] args) => Tool.Run("xdotool", args, TimeSpan.FromSeconds(30), _x);
}
