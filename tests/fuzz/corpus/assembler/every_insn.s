; Every instruction of spec/isa.toml once, with modifiers where allowed (fuzz seed).
l0:
mov r5.xzw, -|r12|.wzyx
add r5.xzw, -|r12|.wzyx, |r33|.y
mul r5.xzw, -|r12|.wzyx, |r33|.y
mad r5.xzw, -|r12|.wzyx, |r33|.y, -r63.zw
dp3 r5.xzw, -|r12|.wzyx, |r33|.y
dp4 r5.xzw, -|r12|.wzyx, |r33|.y
min r5.xzw, -|r12|.wzyx, |r33|.y
max r5.xzw, -|r12|.wzyx, |r33|.y
rcp r5.xzw, -|r12|.wzyx
rsq r5.xzw, -|r12|.wzyx
sqrt r5.xzw, -|r12|.wzyx
frc r5.xzw, -|r12|.wzyx
flr r5.xzw, -|r12|.wzyx
feq r5.xzw, -|r12|.wzyx, |r33|.y
fne r5.xzw, -|r12|.wzyx, |r33|.y
flt r5.xzw, -|r12|.wzyx, |r33|.y
fle r5.xzw, -|r12|.wzyx, |r33|.y
sel r5.xzw, r12.wzyx, r33.y, r63.zw
i2f r5.xzw, r12.wzyx
f2i r5.xzw, -|r12|.wzyx
iadd r5.xzw, r12.wzyx, r33.y
isub r5.xzw, r12.wzyx, r33.y
imul r5.xzw, r12.wzyx, r33.y
imulhu r5.xzw, r12.wzyx, r33.y
and r5.xzw, r12.wzyx, r33.y
or r5.xzw, r12.wzyx, r33.y
xor r5.xzw, r12.wzyx, r33.y
shl r5.xzw, r12.wzyx, r33.y
shr r5.xzw, r12.wzyx, r33.y
sra r5.xzw, r12.wzyx, r33.y
ieq r5.xzw, r12.wzyx, r33.y
ilt r5.xzw, r12.wzyx, r33.y
iltu r5.xzw, r12.wzyx, r33.y
iaddi r5.xzw, r12.wzyx, -5
imuli r5.xzw, r12.wzyx, -5
andi r5.xzw, r12.wzyx, -5
ori r5.xzw, r12.wzyx, -5
xori r5.xzw, r12.wzyx, -5
shli r5.xzw, r12.wzyx, -5
shri r5.xzw, r12.wzyx, -5
srai r5.xzw, r12.wzyx, -5
ilti r5.xzw, r12.wzyx, -5
li r5.xzw, -5
lif r5.xzw, 1.5
ld r5.xzw, [r7.z + 0x20]
ldf r5.xzw, [r7.z + 0x20]
ld1 r5.xzw, [r7.z + 0x20]
ld1f r5.xzw, [r7.z + 0x20]
st [r7.z + 0x20], r5.xzw
st1 [r7.z + 0x20], r5.xzw
push r12.wzyx
pop r5.xzw
bra l0
bz r12.wzyx, l0
bnz r12.wzyx, l0
call l0
calli r12.wzyx
ret
halt
trace r5.xzw, r12.wzyx, r33.y
tracea r5.xzw, r12.wzyx, r33.y
rdsr r5.xzw, launch
