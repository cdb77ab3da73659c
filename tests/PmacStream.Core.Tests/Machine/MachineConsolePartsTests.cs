using PmacStream.GCode;
using PmacStream.Machine;

namespace PmacStream.Core.Tests.Machine;

/// <summary>The console's parts without a controller: status words to alarms, the tables file, the alarm history, the tool table in the profile.</summary>
public sealed class MachineConsolePartsTests : IDisposable
{
    private readonly TestFolder _temp = new("console-parts");

    public void Dispose() => _temp.Dispose();

    [Fact]
    public void The_manuals_example_word_of_a_homed_enabled_motor_carries_no_alarm()
    {
        var w = MotorWord.Parse("88200007C401")!.Value;
        w.HomeComplete.Should().BeTrue();
        w.InPosition.Should().BeTrue();
        w.AmplifierEnabled.Should().BeTrue();
        AlarmText.Decode(w, 1, "X").Should().BeEmpty();
    }

    [Theory]
    [InlineData(1 << 21, 0, "limit+")]
    [InlineData(1 << 22, 0, "limit-")]
    [InlineData(0, 1 << 11, "software-limit")]
    [InlineData(1 << 18, 1 << 3, "amp-fault")]
    [InlineData(1 << 18, (1 << 2) | (1 << 1), "fatal-following-error")]
    [InlineData(0, 1 << 1, "warning-following-error")]
    [InlineData(1 << 18, 0, "motor-killed")]
    public void Each_status_bit_decodes_to_its_stable_code_in_both_languages(int first, int second, string code)
    {
        var w = new MotorWord(first | (1 << 23), second);
        var en = AlarmText.Decode(w, 2, "Y");
        en.Should().ContainSingle().Which.Code.Should().Be(code);
        en[0].Text.Should().Contain("Y axis (motor 2)");
        var zh = AlarmText.Decode(w, 2, "Y", "zh-CN");
        zh[0].Code.Should().Be(code);
        zh[0].Text.Should().Contain("电机 2").And.NotBe(en[0].Text);
        en[0].Severity.Should().Be(code == "warning-following-error" ? AlarmSeverity.Warning : AlarmSeverity.Alarm);
    }

    [Theory]
    [InlineData("G54", 1)]
    [InlineData("g59", 6)]
    [InlineData("G59.2", 8)]
    [InlineData("G54.1P1", 10)]
    [InlineData("G54.1 P48", 57)]
    public void Offset_names_map_to_the_librarys_table_index(string name, int index) =>
        MachineTables.IndexOf(name).Should().Be(index);

    [Fact]
    public void A_bad_offset_name_has_no_index() => MachineTables.IndexOf("G60").Should().BeNull();

    [Fact]
    public void The_tables_file_round_trips_and_names_its_differences()
    {
        var path = Path.Combine(_temp.Path, "tables.json");
        var tables = MachineTables.Empty
            .With(new WorkOffsetEntry("G55", 2, 100, 50, -10))
            .With(new WorkOffsetEntry("G54.1P3", 12, 1, 2, 3))
            .With(new ToolEntry(3, 50.2, 3, 0.1, -0.05));
        tables.Save(path);
        var back = MachineTables.Load(path);
        back.Offset("G55").Should().Be(tables.Offset("G55"));
        back.Offset("G54.1P3").Z.Should().Be(3);
        back.Tool(3).Should().Be(new ToolEntry(3, 50.2, 3, 0.1, -0.05));
        back.Tool(3).EffectiveLength.Should().BeApproximately(50.3, 1e-9);
        back.Differences(tables).Should().BeEmpty();
        MachineTables.Empty.Differences(back).Should().HaveCount(3).And.Contain(d => d.StartsWith("T3:", StringComparison.Ordinal));
    }

    [Fact]
    public void A_broken_tables_file_is_refused_with_its_name()
    {
        var path = Path.Combine(_temp.Path, "bad.json");
        File.WriteAllText(path, "{\"workOffsets\": {\"G60\": [1,2,3]}}");
        var load = () => MachineTables.Load(path);
        load.Should().Throw<InvalidDataException>().WithMessage("*G60*");
    }

    [Fact]
    public void The_history_records_an_alarm_once_and_its_clearing_across_instances()
    {
        var path = Path.Combine(_temp.Path, "alarms.jsonl");
        var limit = new MachineAlarm("limit+", 1, "X", "X on its limit", AlarmSeverity.Alarm);
        var t0 = DateTimeOffset.Parse("2026-01-01T10:00:00Z", System.Globalization.CultureInfo.InvariantCulture);
        new AlarmHistoryFile(path).Observe([limit], t0);
        new AlarmHistoryFile(path).Observe([limit], t0.AddSeconds(1)); // another process sees the same alarm: not new
        new AlarmHistoryFile(path).Observe([], t0.AddSeconds(5));
        var list = new AlarmHistoryFile(path).List();
        list.Should().ContainSingle();
        list[0].Raised.Should().Be(t0);
        list[0].Cleared.Should().Be(t0.AddSeconds(5));
    }

    [Fact]
    public void The_tool_tables_radius_reaches_the_profile_the_check_reads()
    {
        var program = Path.Combine(_temp.Path, "g41.nc");
        File.WriteAllText(program, "G21 G90 G17\nG00 X0 Y-20\nG41 D1 G01 X0 Y0 F600\nY20\nX20\nG40 X40 Y40\nM30\n");
        static IEnumerable<string> Codes(MachineProfile p, string file)
        {
            var found = new List<string>();
            new Checker(p).CheckFile(file, d => found.Add(d.Code), null, CancellationToken.None);
            return found;
        }

        Codes(MachineProfile.Default, program).Should().Contain("E132", "no radius for D1 in the profile");
        var withTable = ToolTableProfile.Apply(MachineProfile.Default, MachineTables.Empty.With(new ToolEntry(1, 0, 3, 0, 0)));
        Codes(withTable, program).Should().NotContain("E132");
        withTable.ToolRadius(1).Should().Be(3);
        ToolTableProfile.Apply(MachineProfile.Default, MachineTables.Empty).Should().BeSameAs(MachineProfile.Default, "no tools: the profile itself");
    }
}
