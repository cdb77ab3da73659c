using System.Globalization;
using PmacStream.Machine;

namespace PmacStream.Hmi;

/// <summary>
/// The Offsets and Tools grids: filled from the controller, validated as the console's tables limit them (numbers,
/// <see cref="MachineTables"/>' ranges), and written on Apply after the operator saw what changes.
/// </summary>
public sealed partial class ConsolePresenter
{
    private static readonly string[] AxisNames = ["X", "Y", "Z"];

    /// <summary>Reads the tables from the controller into the grids (edits not applied are dropped).</summary>
    private async Task ReloadTablesAsync()
    {
        if (!_backend.ConsoleReady)
        {
            return;
        }

        _tables = await _backend.ReadTablesAsync(_life.Token).ConfigureAwait(true);
        _view.OffsetRows = _tables.Offsets.Select(o => (IReadOnlyList<string>)[o.Name, Cell(o.X), Cell(o.Y), Cell(o.Z)]).ToList();
        _view.ToolRows = Enumerable.Range(1, ToolRowCount).Select(n => _tables.Tool(n))
            .Select(t => (IReadOnlyList<string>)[t.Number.ToString(CultureInfo.InvariantCulture), Cell(t.Length), Cell(t.Radius), Cell(t.LengthWear), Cell(t.RadiusWear)]).ToList();
    }

    /// <summary>Validates the offsets grid, shows what differs from the controller, and writes the changed tables once confirmed.</summary>
    private async Task ApplyOffsetsAsync()
    {
        var errors = new List<string>();
        var edited = ParseOffsets(_view.OffsetRows, errors);
        if (await ChangesAsync(errors) is not { } now)
        {
            return;
        }

        var changes = edited.Select(e => (Old: now.Offsets.First(o => o.Index == e.Index), New: e)).Where(c => c.Old != c.New).ToList();
        var lines = changes.Select(c => $"{c.New.Name}: " + string.Join(", ", Enumerable.Range(0, 3).Where(a => c.Old[a] != c.New[a]).Select(a => $"{AxisNames[a]} {Cell(c.Old[a])} → {Cell(c.New[a])}"))).ToList();
        await WriteAsync(lines, changes.Select(c => (Func<Task<ConsoleResult>>)(() => _backend.SetWorkOffsetAsync(c.New.Name, c.New.X, c.New.Y, c.New.Z, _life.Token))).ToList()).ConfigureAwait(true);
    }

    /// <summary>Validates the tools grid, shows what differs from the controller, and writes the changed tools once confirmed.</summary>
    private async Task ApplyToolsAsync()
    {
        var errors = new List<string>();
        var edited = ParseTools(_view.ToolRows, errors);
        if (await ChangesAsync(errors) is not { } now)
        {
            return;
        }

        var changes = edited.Select(e => (Old: now.Tool(e.Number), New: e)).Where(c => c.Old != c.New).ToList();
        var lines = changes.Select(c => string.Create(CultureInfo.InvariantCulture,
            $"T{c.New.Number}: {c.Old.Length}/{c.Old.Radius}/{c.Old.LengthWear}/{c.Old.RadiusWear} → {c.New.Length}/{c.New.Radius}/{c.New.LengthWear}/{c.New.RadiusWear}")).ToList();
        await WriteAsync(lines, changes.Select(c => (Func<Task<ConsoleResult>>)(() =>
            _backend.SetToolAsync(c.New.Number, c.New.Length, c.New.Radius, c.New.LengthWear, c.New.RadiusWear, _life.Token))).ToList()).ConfigureAwait(true);
    }

    /// <summary>The controller's tables to compare the grid with, or null (after showing why) when the grid has errors or no controller is open.</summary>
    private async Task<MachineTables?> ChangesAsync(List<string> errors)
    {
        if (errors.Count > 0)
        {
            _view.TablesMessage = T(TextId.TableNotWritten, string.Join("; ", errors));
            return null;
        }

        if (!_backend.ConsoleReady)
        {
            _view.TablesMessage = HmiText.Get(TextId.ConnectFirst, Language);
            return null;
        }

        return await _backend.ReadTablesAsync(_life.Token).ConfigureAwait(true);
    }

    /// <summary>Shows the differences, asks, writes them one by one (stopping at a refusal) and reads the tables back.</summary>
    private async Task WriteAsync(IReadOnlyList<string> differences, IReadOnlyList<Func<Task<ConsoleResult>>> writes)
    {
        if (differences.Count == 0)
        {
            _view.TablesMessage = HmiText.Get(TextId.TableNoChanges, Language);
            return;
        }

        if (!await _view.ConfirmAsync(HmiText.Get(TextId.ConfirmTablesTitle, Language), T(TextId.ConfirmTablesText, string.Join("\n", differences))).ConfigureAwait(true))
        {
            _view.TablesMessage = HmiText.Get(TextId.Declined, Language);
            return;
        }

        foreach (var write in writes)
        {
            var result = await write().ConfigureAwait(true);
            if (!result.Done)
            {
                _view.TablesMessage = T(TextId.ConsoleRefused, result.Message);
                await ReloadTablesAsync().ConfigureAwait(true);
                return;
            }
        }

        _view.TablesMessage = T(TextId.TableWritten, string.Join("; ", differences));
        _log.Information("Tables written: {Changes:l}", string.Join("; ", differences));
        await ReloadTablesAsync().ConfigureAwait(true);
    }

    /// <summary>The offsets grid as entries; a cell that is not a number or out of range is an error naming its row and column.</summary>
    internal List<WorkOffsetEntry> ParseOffsets(IReadOnlyList<IReadOnlyList<string>> rows, List<string> errors)
    {
        var list = new List<WorkOffsetEntry>();
        foreach (var row in rows)
        {
            if (row.Count < 4 || MachineTables.IndexOf(row[0]) is not { } index)
            {
                continue;
            }

            var v = Enumerable.Range(0, 3).Select(a => Value(row[0], AxisNames[a], row[a + 1], -MachineTables.MaxOffset, MachineTables.MaxOffset, errors)).ToArray();
            list.Add(new WorkOffsetEntry(MachineTables.NameOf(index), index, v[0], v[1], v[2]));
        }

        return list;
    }

    /// <summary>The tools grid as entries, checked as the console's <c>tools set</c> checks them.</summary>
    internal List<ToolEntry> ParseTools(IReadOnlyList<IReadOnlyList<string>> rows, List<string> errors)
    {
        var list = new List<ToolEntry>();
        foreach (var row in rows)
        {
            if (row.Count < 5 || !int.TryParse(row[0], NumberStyles.None, CultureInfo.InvariantCulture, out var n) || n < 1 || n > MachineTables.MaxTool)
            {
                continue;
            }

            var name = "T" + row[0];
            list.Add(new ToolEntry(n,
                Value(name, HmiText.Get(TextId.ColLength, Language), row[1], -MachineTables.MaxLength, MachineTables.MaxLength, errors),
                Value(name, HmiText.Get(TextId.ColRadius, Language), row[2], 0, MachineTables.MaxRadius, errors),
                Value(name, HmiText.Get(TextId.ColLengthWear, Language), row[3], -MachineTables.MaxWear, MachineTables.MaxWear, errors),
                Value(name, HmiText.Get(TextId.ColRadiusWear, Language), row[4], -MachineTables.MaxWear, MachineTables.MaxWear, errors)));
        }

        return list;
    }

    /// <summary>A cell's number (an empty cell is 0), or 0 with an error when it is not a number or out of [min, max].</summary>
    private double Value(string row, string column, string text, double min, double max, List<string> errors)
    {
        var t = text.Trim();
        if (t.Length == 0)
        {
            return 0;
        }

        if (!double.TryParse(t, NumberStyles.Float, CultureInfo.InvariantCulture, out var v) || !double.IsFinite(v))
        {
            errors.Add(T(TextId.TableNumber, row, column, t));
            return 0;
        }

        if (v < min || v > max)
        {
            errors.Add(T(TextId.TableRange, row, column, Cell(v), Cell(min), Cell(max)));
        }

        return v;
    }

    private static string Cell(double v) => v.ToString("0.####", CultureInfo.InvariantCulture);
}
