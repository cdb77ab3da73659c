namespace PmacStream.Preview;

/// <summary>What the legend says, by meaning.</summary>
internal enum LegendTextId
{
    ViewXY,
    ViewXZ,
    ViewYZ,
    ViewIso,
    UnitsInch,
    UnitsMm,
    UnitsMixed,
    NoMoves,
    Moves,
    Executed,
    KeyFeed,
    KeyRapid,
    KeyExecuted,
    KeyRepeated,
    KeyMissing,
    Rotary,
}

/// <summary>The legend's texts in English and Simplified Chinese (format strings with invariant numbers).</summary>
internal static class LegendText
{
    private static readonly Dictionary<LegendTextId, (string En, string Zh)> Table = new()
    {
        [LegendTextId.ViewXY] = ("view XY (X right, Y up)", "视图 XY（X 向右，Y 向上）"),
        [LegendTextId.ViewXZ] = ("view XZ (X right, Z up)", "视图 XZ（X 向右，Z 向上）"),
        [LegendTextId.ViewYZ] = ("view YZ (Y right, Z up)", "视图 YZ（Y 向右，Z 向上）"),
        [LegendTextId.ViewIso] = ("view ISO (X up-right, Y up-left, Z up)", "等轴测视图（X 右上，Y 左上，Z 向上）"),
        [LegendTextId.UnitsInch] = ("units inch (G20)", "单位 英寸 (G20)"),
        [LegendTextId.UnitsMm] = ("units mm (G21)", "单位 毫米 (G21)"),
        [LegendTextId.UnitsMixed] = (", G20/G21 mixed", "，G20/G21 混用"),
        [LegendTextId.NoMoves] = ("no moves to draw", "没有可绘制的运动"),
        [LegendTextId.Moves] = ("moves {0}: {1} linear, {2} arc, {3} rapid", "运动 {0}：直线 {1}，圆弧 {2}，快速 {3}"),
        [LegendTextId.Executed] = ("executed rows {0}, never run {1}, repeated {2}", "已执行记录 {0}，未执行 {1}，重复执行 {2}"),
        [LegendTextId.KeyFeed] = ("feed", "进给"),
        [LegendTextId.KeyRapid] = ("rapid", "快速移动"),
        [LegendTextId.KeyExecuted] = ("executed", "已执行"),
        [LegendTextId.KeyRepeated] = ("executed twice+", "重复执行"),
        [LegendTextId.KeyMissing] = ("never executed", "未执行"),
        [LegendTextId.Rotary] = ("{0}: rotary, not drawn (X Y Z shown)", "{0}：旋转轴，未绘制（仅显示 X Y Z）"),
    };

    /// <summary>The text of <paramref name="id"/>, in Chinese when <paramref name="chinese"/>.</summary>
    public static string Get(LegendTextId id, bool chinese) => chinese ? Table[id].Zh : Table[id].En;

    /// <summary>Every Chinese text joined (to check that the installed fonts can draw them all).</summary>
    public static string AllChinese() => string.Concat(Table.Values.Select(t => t.Zh));
}
